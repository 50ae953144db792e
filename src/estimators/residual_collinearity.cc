#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <limits>
#include <vector>

#include "estimators/residual_assessment.h"

namespace poise::estimators::detail {
namespace {

using Eigen::Index;
using Eigen::MatrixXd;

// Orthonormal basis of the columns of a (numerical rank); empty when a is (near) zero.
MatrixXd basis(const MatrixXd& a) {
  if (a.cols() == 0) return a;
  const double scale = a.norm();
  if (!(scale > 0.0)) return MatrixXd(a.rows(), 0);
  Eigen::ColPivHouseholderQR<MatrixXd> qr(a / scale);
  qr.setThreshold(1e-8);
  const Index r = qr.rank();
  MatrixXd q = qr.householderQ() * MatrixXd::Identity(a.rows(), r);  // not const: returned by move
  return q;
}

}  // namespace

double canonical_correlation(const MatrixXd& a, const MatrixXd& b) {
  const MatrixXd qa = basis(a), qb = basis(b);
  if (qa.cols() == 0 || qb.cols() == 0) return 0.0;
  const MatrixXd c = qa.transpose() * qb;
  Eigen::JacobiSVD<MatrixXd> svd(c);
  const double r = std::min(1.0, svd.singularValues()(0));
  return r < 1e-12 ? 0.0 : r;  // orthogonal to rounding
}

MatrixXd residualize(const MatrixXd& c, const MatrixXd& x) {
  if (x.cols() == 0) return c;
  const MatrixXd q = basis(x);
  return c - q * (q.transpose() * c);
}

std::vector<CandidateCollinearity> plan_collinearity(const Model& base, const ModelData& d, const CandidatePool& pool) {
  const std::vector<Term> c = pool(base);
  const MatrixXd one = MatrixXd::Ones(d.n, 1);
  const MatrixXd h1 = residualize(base.x.leftCols(2), one);
  std::vector<MatrixXd> resid;
  resid.reserve(c.size());
  for (const Term& t : c) resid.push_back(residualize(t.cols, base.x));
  std::vector<CandidateCollinearity> out;
  for (std::size_t i = 0; i < c.size(); ++i) {
    CandidateCollinearity k;
    k.candidate = c[i].name == "step" ? "step (best change point)" : term_label(c[i]);
    k.r_first_harmonic = canonical_correlation(residualize(c[i].cols, one), h1);
    const double r = canonical_correlation(c[i].cols, base.x);
    k.vif_base = r < 1.0 - 1e-12 ? 1.0 / (1.0 - r * r) : std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < c.size(); ++j) {
      if (j == i) continue;
      const double rij = canonical_correlation(resid[i], resid[j]);
      if (rij > k.r_other) k.r_other = rij, k.most_collinear_with = term_label(c[j]);
    }
    out.push_back(std::move(k));
  }
  return out;
}

}  // namespace poise::estimators::detail
