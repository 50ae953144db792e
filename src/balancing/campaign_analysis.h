#pragma once
/// A balancing campaign analysed (poise balance, Python's poise.balance): the influence
/// coefficients calibrated on every run with known masses (check runs left out), the rotor's own
/// unbalance, the least-squares correction and the readings it leaves, and the unbalance of each
/// run of unknown masses and of each check run, all with their 95% regions
/// (estimators/balancing_prediction.h). A check run's answer is compared with its known masses.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "balancing/campaign.h"
#include "estimators/balancing_model_tests.h"
#include "estimators/balancing_prediction.h"

namespace poise::balancing {

/// The answer for one declared run that the calibration did not use.
struct RunAnswer {
  std::string name;
  std::size_t declared = 0;  ///< the [[run]]'s index
  bool check = false;
  std::size_t readings = 0;                                ///< rows averaged
  estimators::PlaneAnswers unbalance;                      ///< per plane, g at its radius; static/couple below
  std::optional<std::vector<estimators::Phasor>> applied;  ///< a check run's masses
};

/// A correction mass split onto the two holes beside it (a plane with `holes`).
struct HoleMass {
  double angle = 0.0;  ///< rad, declared sense
  double mass_g = 0.0;
};

/// One reading of a run and what the calibration makes of it: the fitted reading a + H w of a
/// run it used, the reading predicted from a check run's known masses; none for an unknown run.
struct ReadingPoint {
  std::string run;
  std::size_t sensor = 0;
  estimators::Phasor reading;
  std::optional<estimators::Phasor> model;
  bool check = false;
};

struct CampaignAnalysis {
  std::optional<double> speed_rpm;  ///< the speed these readings were taken at, where given
  estimators::InfluenceCalibration calibration;
  estimators::Correction correction;  ///< the plain least-squares correction
  estimators::PlaneAnswers correction_masses, initial_unbalance;
  std::vector<estimators::PhasorInterval> residual_readings;  ///< as Poise counts (lag, probe angle added)
  std::vector<estimators::PhasorInterval> residual_as_read;   ///< as the instrument will show them
  std::vector<std::vector<HoleMass>> correction_holes;        ///< per plane; empty where any angle will do
  std::vector<ReadingPoint> points;
  std::vector<RunAnswer> runs;
  /// The linear model's tests on these runs (estimators/balancing_model_tests.h), and the runout
  /// test across the speeds (on the balancing speed's analysis).
  std::vector<estimators::ModelTest> model_tests;
  /// Static and couple unbalance: "g mm" where every plane's radius is given, else "g" (at the
  /// planes' radii), and the factor from the estimators' figures (g m or g) to that unit.
  std::string moment_unit;
  double moment_factor = 1.0;
  std::string answer;  ///< the campaign's answer in one sentence
};

/// The correction w split onto the two of `holes` equally spaced holes (the first at `first`,
/// rad) beside its angle: m_a e^{i phi_a} + m_b e^{i phi_b} = w, both masses >= 0.
std::vector<HoleMass> split_onto_holes(const estimators::Phasor& w, int holes, double first);

/// One analysis per speed of the readings (one where none is given), the balancing speed's first
/// (the campaign's balancing_speed, else the highest). Throws poise::Error when the campaign
/// cannot be calibrated at the balancing speed (too few runs, planes not separated, fewer
/// sensors than planes); another speed that cannot be is left out with a note.
/// A real figure beside the simulated distribution of a design study's output ([design]).
struct DesignComparison {
  std::string figure, plane, output, unit;
  std::optional<double> real;  ///< in the output's unit; absent where the campaign has no such figure
  double share_below = 0.0;    ///< simulated machines at or below the real figure
  double p2_5 = 0.0, p97_5 = 0.0;
  std::size_t samples = 0;
  bool within = false;
  std::string sentence;
};

/// One real influence coefficient against the design study's mean, before and after a calibration.
struct CalibrationFigure {
  std::string sensor, plane, output, unit;
  double real = 0.0, real_se = 0.0;  ///< |h| from the readings, in the output's unit, and its standard error
  double before = 0.0, after = 0.0;  ///< the study's mean |h|: as the model is, and at the fitted value
};

/// A model key of the design study fitted to the real influence coefficients ([design.calibrate]):
/// the value that makes the study's mean |h| equal the real ones in weighted least squares (weights
/// from the machines' covariance and the readings' errors, cli/balance_calibration.h). A calibration to these
/// readings, not a validation of the model.
struct DesignCalibration {
  std::string key, unit;
  double value = 0.0;  ///< fitted, in `unit`
  double se = 0.0;     ///< its standard error (cli/balance_calibration.h)
  double low = 0.0, high = 0.0;
  bool at_bound = false;  ///< the fit ended at an end of the range: the range holds no better value
  double chi2_before = 0.0, chi2_after = 0.0;
  std::size_t dof = 0;          ///< figures - 1
  std::size_t evaluations = 0;  ///< design-study runs of `samples` machines each
  std::vector<CalibrationFigure> figures;
  std::string sentence;
};

/// What the design study says of the campaign: the real figures placed, and the calibration.
struct DesignResult {
  std::vector<DesignComparison> comparisons;
  std::optional<DesignCalibration> calibration;
};

struct CampaignAnalyses {
  std::vector<CampaignAnalysis> speeds;
  std::vector<std::string> notes;
  std::vector<DesignComparison> design;
  std::optional<DesignCalibration> calibration;
};

/// Runs a campaign's design study and places the real figures (cli/balance_design.h: it needs
/// the study kinds, a layer above this one).
using DesignRunner = std::function<DesignResult(const BalancingCampaign&, const CampaignAnalysis&)>;

/// With a [design] and a runner, the comparisons join the balancing speed's answer.
CampaignAnalyses analyse_campaign(const BalancingCampaign& c, const DesignRunner& design = {});

/// The analysis as `poise balance --json` prints it: the balancing speed's figures at the top,
/// and with several speeds each speed's under "speeds".
nlohmann::json analysis_json(const BalancingCampaign& c, const CampaignAnalyses& a);

/// A correction's split onto holes: "24.13 g @ 292.5 deg and 16.08 g @ 315.0 deg".
std::string holes_text(const std::vector<HoleMass>& holes);

/// "15.33 g @ 2.9 deg" and, with a region, " (95%: +- 1.2 g)".
std::string phasor_text(const estimators::PhasorInterval& z, const std::string& unit, double factor = 1.0);

/// An angle in degrees in [0, 360).
double degrees(const estimators::Phasor& z);

}  // namespace poise::balancing
