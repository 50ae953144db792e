#include "sampling/distribution.h"

#include <boost/math/special_functions/erf.hpp>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/format.h"
#include "core/units.h"

namespace poise::sampling {
namespace {
constexpr double kSqrt2 = 1.41421356237309504880;
constexpr double kSqrt3 = 1.73205080756887729353;

double sigmas_of(ToleranceConvention c) {
  switch (c) {
    case ToleranceConvention::kOneSigma: return 1.0;
    case ToleranceConvention::kTwoSigma: return 2.0;
    case ToleranceConvention::kThreeSigma: return 3.0;
    case ToleranceConvention::kBounds: return 0.0;
  }
  return 0.0;
}
}  // namespace

// Boost's double-precision erfc_inv (its rational approximations for double, 1-2 ulp) rather than
// the default, which promotes to long double: the draw of every sample goes through it, and the
// long-double path took two thirds of a closed-form run's CPU (issue 54's profile).
double standard_normal_quantile(double u) {
  using DoublePolicy = boost::math::policies::policy<boost::math::policies::promote_double<false>>;
  return -kSqrt2 * boost::math::erfc_inv(2.0 * u, DoublePolicy());
}
double standard_normal_cdf(double x) { return 0.5 * boost::math::erfc(-x / kSqrt2); }

DistributionKind parse_distribution_kind(std::string_view name) {
  if (name == "normal") return DistributionKind::kNormal;
  if (name == "uniform") return DistributionKind::kUniform;
  if (name == "arcsine") return DistributionKind::kArcsine;
  if (name == "truncated_normal") return DistributionKind::kTruncatedNormal;
  if (name == "fixed") return DistributionKind::kFixed;
  throw Error("unknown distribution \"" + std::string(name) + "\"; expected one of " + distribution_kind_names());
}

ToleranceConvention parse_convention(std::string_view name) {
  if (name == "bounds") return ToleranceConvention::kBounds;
  if (name == "1sigma") return ToleranceConvention::kOneSigma;
  if (name == "2sigma") return ToleranceConvention::kTwoSigma;
  if (name == "3sigma") return ToleranceConvention::kThreeSigma;
  throw Error("unknown tolerance convention \"" + std::string(name) + "\"; expected one of " + convention_names());
}

std::string distribution_kind_names() {
  return "\"normal\", \"uniform\", \"arcsine\", \"truncated_normal\", \"fixed\"";
}
std::string convention_names() { return "\"bounds\", \"1sigma\", \"2sigma\", \"3sigma\""; }

std::string to_string(DistributionKind kind) {
  switch (kind) {
    case DistributionKind::kNormal: return "normal";
    case DistributionKind::kUniform: return "uniform";
    case DistributionKind::kArcsine: return "arcsine";
    case DistributionKind::kTruncatedNormal: return "truncated_normal";
    case DistributionKind::kFixed: return "fixed";
  }
  return "?";
}

std::string to_string(ToleranceConvention c) {
  switch (c) {
    case ToleranceConvention::kBounds: return "bounds";
    case ToleranceConvention::kOneSigma: return "1sigma";
    case ToleranceConvention::kTwoSigma: return "2sigma";
    case ToleranceConvention::kThreeSigma: return "3sigma";
  }
  return "?";
}

Distribution::Distribution(DistributionKind kind, double nominal, double tolerance, ToleranceConvention convention)
    : kind_(kind), convention_(convention), nominal_(nominal), tolerance_(tolerance) {
  if (!std::isfinite(nominal) || !std::isfinite(tolerance)) {
    throw Error("distribution parameters must be finite");
  }
  if (tolerance < 0.0) throw Error("a tolerance must not be negative");
  const double k = sigmas_of(convention);
  switch (kind) {
    case DistributionKind::kNormal:
      if (convention == ToleranceConvention::kBounds) {
        throw Error(
            "a normal distribution has no bounds: say tolerance_is = \"3sigma\" (or 1sigma, "
            "2sigma), or use truncated_normal");
      }
      sigma_ = tolerance / k;
      break;
    case DistributionKind::kUniform:
      half_width_ = convention == ToleranceConvention::kBounds ? tolerance : kSqrt3 * tolerance / k;
      break;
    case DistributionKind::kArcsine:
      half_width_ = convention == ToleranceConvention::kBounds ? tolerance : kSqrt2 * tolerance / k;
      break;
    case DistributionKind::kTruncatedNormal:
      if (convention == ToleranceConvention::kBounds) {
        throw Error(
            "a truncated normal needs its sigma: say tolerance_is = \"2sigma\" (cut at +-2 sigma) "
            "or \"3sigma\"; the tolerance is the cut");
      }
      sigma_ = tolerance / k;
      half_width_ = tolerance;
      phi_lo_ = standard_normal_cdf(-k);
      break;
    case DistributionKind::kFixed: break;
  }
}

double Distribution::centered_quantile(double u) const {
  switch (kind_) {
    case DistributionKind::kNormal: return sigma_ * standard_normal_quantile(u);
    case DistributionKind::kUniform: return half_width_ * (2.0 * u - 1.0);
    case DistributionKind::kArcsine: return half_width_ * std::sin(units::kPi * (u - 0.5));
    case DistributionKind::kTruncatedNormal: {
      if (sigma_ == 0.0) return 0.0;
      const double p = phi_lo_ + u * (1.0 - 2.0 * phi_lo_);
      return sigma_ * standard_normal_quantile(p);
    }
    case DistributionKind::kFixed: return tolerance_;
  }
  return 0.0;
}

double Distribution::quantile(double u) const { return nominal_ + centered_quantile(u); }

double Distribution::magnitude_quantile(double u) const {
  if (kind_ == DistributionKind::kFixed) return std::abs(tolerance_);
  // |X| for X symmetric about zero: P(|X| <= x) = 2 F(x) - 1.
  return std::abs(centered_quantile(0.5 * (1.0 + u)));
}

double Distribution::stddev() const {
  switch (kind_) {
    case DistributionKind::kNormal: return sigma_;
    case DistributionKind::kUniform: return half_width_ / kSqrt3;
    case DistributionKind::kArcsine: return half_width_ / kSqrt2;
    case DistributionKind::kTruncatedNormal: {
      if (sigma_ == 0.0) return 0.0;
      const double k = half_width_ / sigma_;
      const double pdf = std::exp(-0.5 * k * k) / std::sqrt(2.0 * units::kPi);
      const double z = 1.0 - 2.0 * phi_lo_;
      return sigma_ * std::sqrt(1.0 - 2.0 * k * pdf / z);
    }
    case DistributionKind::kFixed: return 0.0;
  }
  return 0.0;
}

double Distribution::lower() const {
  switch (kind_) {
    case DistributionKind::kNormal: return sigma_ > 0 ? -std::numeric_limits<double>::infinity() : nominal_;
    case DistributionKind::kFixed: return nominal_ + tolerance_;
    default: return nominal_ - half_width_;
  }
}

double Distribution::upper() const {
  switch (kind_) {
    case DistributionKind::kNormal: return sigma_ > 0 ? std::numeric_limits<double>::infinity() : nominal_;
    case DistributionKind::kFixed: return nominal_ + tolerance_;
    default: return nominal_ + half_width_;
  }
}

std::string Distribution::describe(double display_factor, std::string_view unit) const {
  const double t = tolerance_ / display_factor;
  switch (kind_) {
    case DistributionKind::kFixed:
      return fmt::format("fixed at {:.4g} {}", (nominal_ + tolerance_) / display_factor, unit);
    case DistributionKind::kNormal:
      return fmt::format("normal, +-{:.4g} {} read as {} (sigma = {:.4g} {})", t, unit, to_string(convention_),
                         stddev() / display_factor, unit);
    default:
      return fmt::format("{}, +-{:.4g} {} read as {} (support +-{:.4g} {}, sigma = {:.4g} {})", to_string(kind_), t,
                         unit, to_string(convention_), half_width_ / display_factor, unit, stddev() / display_factor,
                         unit);
  }
}

}  // namespace poise::sampling
