#pragma once
/// Tolerance distributions with explicit sigma conventions.
///
/// A tolerance is written "+-t about a nominal", and the file says how to read t:
///   tolerance_is = "bounds"  : t is the half-width of the support (uniform, arcsine,
///                              truncated normal need it; normal cannot have bounds)
///   tolerance_is = "1sigma" | "2sigma" | "3sigma" : t is k standard deviations.
/// Kinds and their parameters for half-width a or standard deviation s:
///   normal            N(0, s^2),                      s = t/k
///   uniform           U(-a, a),  s = a/sqrt(3);       a = t (bounds) or sqrt(3) t/k
///   arcsine           a sin(pi (u - 1/2)), s = a/sqrt(2); a = t (bounds) or sqrt(2) t/k
///   truncated_normal  N(0, s^2) cut at +-t,           s = t/k (k >= 1; "bounds" refused)
///   fixed             always the nominal + t (a worst case / a declared value)
/// Sampling is by the inverse CDF of a uniform variate, so plain MC, Latin hypercube
/// and Sobol designs all feed the same code.
#include <string>
#include <string_view>

namespace poise::sampling {

enum class DistributionKind { kNormal, kUniform, kArcsine, kTruncatedNormal, kFixed };
enum class ToleranceConvention { kBounds, kOneSigma, kTwoSigma, kThreeSigma };

/// Parses "normal", "uniform", "arcsine", "truncated_normal", "fixed"; throws poise::Error.
DistributionKind parse_distribution_kind(std::string_view name);
/// Parses "bounds", "1sigma", "2sigma", "3sigma"; throws poise::Error.
ToleranceConvention parse_convention(std::string_view name);
std::string to_string(DistributionKind kind);
std::string to_string(ToleranceConvention convention);
/// The list of accepted names, for error messages.
std::string distribution_kind_names();
std::string convention_names();

/// A one-dimensional distribution defined by a nominal, a tolerance and how to read it.
class Distribution {
 public:
  /// Throws poise::Error naming the offending combination (e.g. normal with bounds,
  /// negative tolerance).
  Distribution(DistributionKind kind, double nominal, double tolerance, ToleranceConvention convention);

  /// Inverse CDF at u in (0, 1).
  double quantile(double u) const;
  /// Inverse CDF of |X - nominal| (the folded deviation), for magnitudes such as run-out.
  double magnitude_quantile(double u) const;
  double mean() const { return nominal_ + (kind_ == DistributionKind::kFixed ? tolerance_ : 0.0); }
  /// Standard deviation of X.
  double stddev() const;
  /// Lower and upper end of the support (+-infinity for normal).
  double lower() const;
  double upper() const;

  DistributionKind kind() const { return kind_; }
  ToleranceConvention convention() const { return convention_; }
  double nominal() const { return nominal_; }
  double tolerance() const { return tolerance_; }
  /// "normal, +-t read as 3 sigma (sigma = t/3)" style description for reports.
  std::string describe(double display_factor, std::string_view unit) const;

 private:
  double centered_quantile(double u) const;

  DistributionKind kind_;
  ToleranceConvention convention_;
  double nominal_;
  double tolerance_;
  double sigma_ = 0.0;       // normal, truncated normal
  double half_width_ = 0.0;  // uniform, arcsine, truncated normal cut
  double phi_lo_ = 0.0;      // truncated normal: Phi(-a/s)
};

/// Standard normal inverse CDF (Boost.Math, full double accuracy).
double standard_normal_quantile(double u);
double standard_normal_cdf(double x);

}  // namespace poise::sampling
