#include "sampling/sensitivity.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/format.h"
#include "sampling/random_stream.h"

namespace poise::sampling {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Every estimate is a function of weighted column sums over the base rows: a resample
// is a vector of counts w_j (how often row j was drawn), the data itself is w_j = 1.
// Per base row j, with a = fA_j - c, b = fB_j - c (c = the pooled mean on the data, a
// fixed shift for conditioning) and d = fAB_j - fA_j, the columns are
//   [0] a   [1] b   [2] a^2 + b^2                         (the total variance)
//   per group g: b d, d, d^2 (0 where row j is not in R_g), and, only for a group
//   with rows missing, the indicator of R_g (else its count is the resample size).
struct Layout {
  std::size_t cols = 3;
  std::vector<std::size_t> group_col;  // first of the three columns of group g
  std::vector<std::size_t> count_col;  // indicator column of group g, or npos
};

constexpr std::size_t npos = static_cast<std::size_t>(-1);

// Indices from the column sums s of a sample of n base rows.
struct Replicate {
  double variance = kNaN;
  std::vector<double> first, total;
  double first_sum = kNaN;
};

void indices_from_sums(const Layout& layout, const double* s, double n, Replicate& r) {
  const std::size_t k = layout.group_col.size();
  r.first.assign(k, kNaN);
  r.total.assign(k, kNaN);
  r.first_sum = kNaN;
  if (n < 2.0) return;
  const double m = (s[0] + s[1]) / (2.0 * n);  // mean of the shifted pooled values
  const double v = std::max(0.0, (s[2] - 2.0 * n * m * m) / (2.0 * n - 1.0));
  r.variance = v;
  if (!(v > 0.0)) return;
  double sum = 0.0;
  for (std::size_t g = 0; g < k; ++g) {
    const double* q = s + layout.group_col[g];
    const double ng = layout.count_col[g] == npos ? n : s[layout.count_col[g]];
    if (!(ng > 0.0)) {
      sum = kNaN;
      continue;
    }
    // sum (b - m) d = sum b d - m sum d.
    r.first[g] = (q[0] - m * q[1]) / ng / v;
    r.total[g] = q[2] / (2.0 * ng) / v;
    sum += r.first[g];
  }
  r.first_sum = sum;
}

// Percentile interval and standard error of the finite bootstrap replicates.
struct Spread {
  std::optional<double> lo, hi;
  double se = 0.0;
};

Spread spread(std::vector<double>& reps) {
  std::erase_if(reps, [](double x) { return !std::isfinite(x); });
  Spread out;
  if (reps.size() < 2) return out;
  const double nr = static_cast<double>(reps.size());
  double mean = 0.0;
  for (double x : reps) mean += x;
  mean /= nr;
  double ss = 0.0;
  for (double x : reps) ss += (x - mean) * (x - mean);
  out.se = std::sqrt(ss / (nr - 1.0));
  out.lo = quantile_value(reps, 0.025);
  out.hi = quantile_value(reps, 0.975);
  return out;
}

Estimate with_spread(double value, const Spread& s) { return {value, s.lo, s.hi, {}}; }

void check_sobol_inputs(std::span<const double> fA, std::span<const double> fB,
                        const std::vector<std::span<const double>>& fAB) {
  const std::size_t N = fA.size(), k = fAB.size();
  require(fB.size() == N,
          "Sobol indices: f(A) has " + std::to_string(N) + " values but f(B) has " + std::to_string(fB.size()));
  require(k > 0, "Sobol indices need at least one input group");
  for (std::size_t g = 0; g < k; ++g) {
    require(fAB[g].size() == N, "Sobol indices: f(AB) of group " + std::to_string(g) + " has " +
                                    std::to_string(fAB[g].size()) + " values, expected " + std::to_string(N));
  }
}

// The base rows R (f(A) and f(B) finite), each group's rows R_g counted into res, and the
// column layout they give.
struct BaseRows {
  std::vector<std::size_t> rows;
  Layout layout;
};

BaseRows base_rows(std::span<const double> fA, std::span<const double> fB,
                   const std::vector<std::span<const double>>& fAB, SobolResult& res) {
  const std::size_t N = fA.size(), k = fAB.size();
  BaseRows out;
  std::vector<std::size_t>& base = out.rows;
  base.reserve(N);
  for (std::size_t j = 0; j < N; ++j) {
    if (std::isfinite(fA[j]) && std::isfinite(fB[j])) base.push_back(j);
  }
  const std::size_t n = base.size();
  Layout& layout = out.layout;
  layout.group_col.resize(k);
  layout.count_col.assign(k, npos);
  for (std::size_t g = 0; g < k; ++g) {
    std::size_t used = 0;
    for (std::size_t j : base) used += std::isfinite(fAB[g][j]) ? 1 : 0;
    res.groups[g].rows_used = used;
    layout.group_col[g] = layout.cols;
    layout.cols += 3;
  }
  for (std::size_t g = 0; g < k; ++g) {
    if (res.groups[g].rows_used < n) layout.count_col[g] = layout.cols++;
  }
  return out;
}

// Row-major table of the columns (n x cols) of the base rows, shifted by `shift`.
std::vector<double> column_table(std::span<const double> fA, std::span<const double> fB,
                                 const std::vector<std::span<const double>>& fAB, const BaseRows& rows, double shift) {
  const std::vector<std::size_t>& base = rows.rows;
  const Layout& layout = rows.layout;
  const std::size_t n = base.size(), k = fAB.size();
  const std::size_t C = layout.cols;
  std::vector<double> X(n * C, 0.0);
  for (std::size_t r = 0; r < n; ++r) {
    const std::size_t j = base[r];
    double* x = X.data() + r * C;
    const double a = fA[j] - shift, b = fB[j] - shift;
    x[0] = a;
    x[1] = b;
    x[2] = a * a + b * b;
    for (std::size_t g = 0; g < k; ++g) {
      if (!std::isfinite(fAB[g][j])) continue;
      const double d = fAB[g][j] - fA[j];
      double* q = x + layout.group_col[g];
      q[0] = b * d;
      q[1] = d;
      q[2] = d * d;
      if (layout.count_col[g] != npos) x[layout.count_col[g]] = 1.0;
    }
  }
  return X;
}

// The bootstrap replicates of every index (per group: first, total; and the first-order sum).
struct BootstrapReplicates {
  std::vector<std::vector<double>> first, total;
  std::vector<double> first_sum;
};

// Bootstrap: resamples in batches of kBatch. A resample is the count w_r of each base
// row (how often it was drawn); one pass over the table per batch accumulates w_r x_r into
// each resample's sums, so the table is read once per batch, not once per resample.
BootstrapReplicates bootstrap(const std::vector<double>& X, const Layout& layout, std::size_t n, std::uint64_t seed,
                              std::size_t bootstrap_resamples) {
  const std::size_t k = layout.group_col.size(), C = layout.cols;
  const std::size_t B = bootstrap_resamples;
  BootstrapReplicates out{std::vector<std::vector<double>>(k, std::vector<double>(B)),
                          std::vector<std::vector<double>>(k, std::vector<double>(B)), std::vector<double>(B)};
  std::vector<std::vector<double>>& first_reps = out.first;
  std::vector<std::vector<double>>& total_reps = out.total;
  std::vector<double>& sum_reps = out.first_sum;
  constexpr std::size_t kBatch = 8;
  std::vector<std::uint32_t> w(kBatch * n);  // [resample in batch][row], one resample's in cache
  std::vector<double> acc(kBatch * C);
  const double nn = static_cast<double>(n);
  const std::uint64_t n32 = n;
  Replicate rep;
  for (std::size_t r0 = 0; r0 < B; r0 += kBatch) {
    const std::size_t nb = std::min(kBatch, B - r0);
    std::fill(w.begin(), w.end(), 0u);
    std::fill(acc.begin(), acc.end(), 0.0);
    for (std::size_t b = 0; b < nb; ++b) {
      // Two draws per 64 random bits: row = floor(h n / 2^32) for each 32-bit half h
      // (uniform up to a relative n / 2^32, far below the bootstrap's own noise).
      RandomStream rs(seed, StreamId::kBootstrap, r0 + b);
      std::uint32_t* wb = w.data() + b * n;
      for (std::size_t i = 0; i < n; i += 2) {
        const std::uint64_t bits = rs.next_bits();
        ++wb[((bits >> 32) * n32) >> 32];
        if (i + 1 < n) ++wb[((bits & 0xffffffffu) * n32) >> 32];
      }
    }
    for (std::size_t r = 0; r < n; ++r) {
      const double* x = X.data() + r * C;
      for (std::size_t b = 0; b < nb; ++b) {
        const std::uint32_t c = w[b * n + r];
        if (c == 0) continue;  // a row not drawn (37% of them on average)
        const double cw = c;
        double* a = acc.data() + b * C;
        for (std::size_t col = 0; col < C; ++col) a[col] += cw * x[col];
      }
    }
    for (std::size_t b = 0; b < nb; ++b) {
      indices_from_sums(layout, acc.data() + b * C, nn, rep);
      for (std::size_t g = 0; g < k; ++g) {
        first_reps[g][r0 + b] = rep.first[g];
        total_reps[g][r0 + b] = rep.total[g];
      }
      sum_reps[r0 + b] = rep.first_sum;
    }
  }
  return out;
}

// Each index's percentile interval and standard error from its replicates.
void set_spreads(BootstrapReplicates& reps, SobolResult& res) {
  for (std::size_t g = 0; g < res.groups.size(); ++g) {
    const Spread sf = spread(reps.first[g]), st = spread(reps.total[g]);
    res.groups[g].first = with_spread(res.groups[g].first.value, sf);
    res.groups[g].total = with_spread(res.groups[g].total.value, st);
    res.groups[g].first_se = sf.se;
    res.groups[g].total_se = st.se;
  }
  const Spread ss = spread(reps.first_sum);
  res.first_sum = with_spread(res.first_sum.value, ss);
  res.first_sum_se = ss.se;
}

}  // namespace

SobolResult sobol_indices(std::span<const double> fA, std::span<const double> fB,
                          const std::vector<std::span<const double>>& fAB, std::uint64_t seed,
                          std::size_t bootstrap_resamples) {
  check_sobol_inputs(fA, fB, fAB);
  const std::size_t N = fA.size(), k = fAB.size();
  SobolResult res;
  res.groups.resize(k);
  res.first_sum.value = kNaN;
  for (auto& gi : res.groups) gi.first.value = gi.total.value = kNaN;
  res.variance = kNaN;

  // Base rows R and the per-group rows R_g.
  const BaseRows rows = base_rows(fA, fB, fAB, res);
  const std::size_t n = rows.rows.size();
  res.n = n;
  if (n < 2) {
    res.note = "fewer than 2 rows with f(A) and f(B) both finite (" + std::to_string(n) + " of " + std::to_string(N) +
               "): indices undefined";
    return res;
  }

  // Shift and constant-output check.
  double shift = 0.0, max_abs = 0.0;
  for (std::size_t j : rows.rows) {
    shift += fA[j] + fB[j];
    max_abs = std::max({max_abs, std::abs(fA[j]), std::abs(fB[j])});
  }
  shift /= 2.0 * static_cast<double>(n);
  const std::vector<double> X = column_table(fA, fB, fAB, rows, shift);

  // Estimates on the data.
  const std::size_t C = rows.layout.cols;
  std::vector<double> sums(C, 0.0);
  for (std::size_t r = 0; r < n; ++r) {
    const double* x = X.data() + r * C;
    for (std::size_t c = 0; c < C; ++c) sums[c] += x[c];
  }
  Replicate est;
  indices_from_sums(rows.layout, sums.data(), static_cast<double>(n), est);
  res.variance = est.variance;
  if (!(std::sqrt(est.variance) > kConstantOutputTolerance * max_abs)) {
    res.note = fmt::format("constant output (standard deviation {:.3g} <= {:.0e} x max |f| = {:.6g})",
                           std::sqrt(est.variance), kConstantOutputTolerance, max_abs) +
               ": indices undefined";
    return res;
  }
  for (std::size_t g = 0; g < k; ++g) {
    res.groups[g].first.value = est.first[g];
    res.groups[g].total.value = est.total[g];
    if (res.groups[g].rows_used == 0) {
      res.note += std::string(res.note.empty() ? "" : "; ") + "group " + std::to_string(g) +
                  ": no row with f(A), f(B) and f(AB) all finite, indices undefined";
    }
  }
  res.first_sum.value = est.first_sum;
  if (bootstrap_resamples == 0) return res;
  require(n < (std::uint64_t{1} << 32), "Sobol indices: bootstrap limited to 2^32 rows");
  BootstrapReplicates reps = bootstrap(X, rows.layout, n, seed, bootstrap_resamples);
  set_spreads(reps, res);
  return res;
}

}  // namespace poise::sampling
