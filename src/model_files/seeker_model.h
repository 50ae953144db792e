#pragma once
/// The two-axis seeker model file (models/seeker_two_axis_*.toml): geometry, every
/// tolerance with its distribution, the values a source document declares, and the
/// mapping from a design point to one realization of the errors (SeekerErrorState).
///
/// Error sources and their geometric meaning (see models/seeker_los_chain.h):
///   yaw.perpendicularity     Delta over the yaw span L1 -> static tilt of the yaw axis, read
///                            as the model file's `direction` and `sigma_of` say:
///                            "random" + "magnitude" (default): |X|/L1 towards a uniformly random
///                              azimuth (the tolerance is the tilt's magnitude: each component
///                              has sigma/sqrt 2);
///                            "random" + "component": X1/L1 and X2/L1 independently along x and y
///                              (the tolerance is per component: the magnitude is Rayleigh-like,
///                              RMS sqrt 2 sigma);
///                            "fixed": signed X/L1 along `azimuth` (default 0 deg, the yaw
///                              frame's x axis), the paper's single-direction reading.
///   pitch.perpendicularity   X/L2 -> pitch axis tilt towards the yaw axis (signed)
///   optics.axis_error        X/L3 -> optical axis off perpendicular to the pitch axis
///   <axis>.radial_runout, face_runout, clearance, bore_roundness (scaled by k'):
///   <axis>.ball_roundness, seat_deformation (not scaled):
///                            at each of the two bearings a shaft-centre displacement
///                            |X| (cos(n phi + psi), sin(n phi + psi)) with its own random
///                            phase psi; n = `order` (1 turns with the shaft, 0 static)
///   load_deformation         k', the paper's load-deformation factor
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "engine/study_files/input_column.h"
#include "engine/study_files/model_overrides.h"
#include "engine/study_files/tolerance_spec.h"
#include "geometry/generators.h"
#include "models/seeker_los_budget.h"
#include "models/seeker_los_chain.h"

namespace poise::model_files {
using engine::InputColumn;
using engine::ModelHeader;
using engine::ToleranceSpec;
using engine::ValidationError;

/// A displacement source at the bearings of one axis.
struct BearingSource {
  std::string name;          ///< "radial_runout", ...
  ToleranceSpec spec;        ///< amplitude per bearing (m)
  double order = 1.0;        ///< cycles per shaft turn
  bool load_scaled = false;  ///< multiplied by k'
};

/// How the yaw perpendicularity's tilt is drawn (see above).
struct TiltReading {
  bool random_direction = true;  ///< direction = "random" | "fixed"
  bool per_component = false;    ///< sigma_of = "component" | "magnitude" (random only)
  double azimuth = 0.0;          ///< rad, direction = "fixed"
  std::string describe() const;  ///< e.g. "random direction, tolerance of the magnitude"
};
struct SeekerAxis {
  double span = 0.0;  ///< bearing span L (m)
  ToleranceSpec perpendicularity;
  TiltReading tilt_reading;  ///< yaw only (the pitch tilt is towards the yaw axis by definition)
  std::vector<BearingSource> bearing_sources;
};

struct SeekerModel : ModelHeader {                                ///< file, name, title, source of the model file
  double yaw_min = 0, yaw_max = 0, pitch_min = 0, pitch_max = 0;  ///< rad
  double pixel_ifov = 0;                                          ///< rad per pixel
  std::string pixel_ifov_source;
  ToleranceSpec load_deformation;  ///< k'
  SeekerAxis yaw, pitch;
  double barrel_length = 0;  ///< L3 (m)
  ToleranceSpec optical_axis;
  /// Frames and housing ([geometry], optional; model_files/seeker_geometry.h), sized from the spans.
  std::optional<geometry::SeekerGeometry> geometry;
  /// [geometry] ring_mesh, barrel_mesh, housing_mesh: a designer's meshes (checked, in metres,
  /// each in its frame's coordinates) used instead of the generated yaw ring, pitch barrel and
  /// housing; null = generated from the [geometry] dimensions. Shared: the model is copied.
  struct UserMeshes {
    std::shared_ptr<const geometry::Mesh> ring, barrel, housing;
    std::string ring_file, barrel_file, housing_file;  ///< as resolved
  } meshes;

  /// Dotted keys of every tolerance table ("yaw.perpendicularity", "yaw.radial_runout", ...).
  std::vector<std::string> tolerance_keys() const;
  /// Inputs of Wang 2011's analytic budget method from the same numbers (the budget itself is a
  /// reviewer's budget file, `poise budget`; tests check that file against this).
  models::WangBudgetInputs budget_inputs() const;
};

/// Loads and validates a model file; `overrides` replace values by dotted key before
/// validation ("yaw.bearing_span" -> "100 mm"). Throws ValidationError with every problem.
SeekerModel load_seeker_model(const std::string& path, const std::map<std::string, std::string>& overrides = {});

/// Maps unit-hypercube points to error realizations. Immutable, thread-safe.
class SeekerSampler {
 public:
  explicit SeekerSampler(SeekerModel model);
  std::size_t dimension() const { return columns_.size(); }
  const std::vector<InputColumn>& columns() const { return columns_; }
  /// The model file's tolerance key of each column ("yaw.radial_runout" for its amplitude and
  /// phase at both bearings): the columns of one key form its group in the Sobol indices.
  const std::vector<std::string>& column_tolerances() const { return column_tolerances_; }
  /// u: design point (size dimension()); values: drawn inputs in display units (same size).
  models::SeekerErrorState draw(std::span<const double> u, std::span<double> values) const;
  /// The error realization of input values in SI, in columns()' order (display value x
  /// display_factor): what draw() returns for the values it draws.
  models::SeekerErrorState state_of(std::span<const double> si) const;
  /// The nominal unit's input values in display units: load factor at its median, every
  /// tilt, axis error and run-out amplitude zero (phases and a random azimuth 0).
  std::vector<double> nominal() const;

 private:
  SeekerModel model_;
  std::vector<InputColumn> columns_;
  std::vector<std::string> column_tolerances_;
};

}  // namespace poise::model_files
