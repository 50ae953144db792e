#include "model_files/seeker_model.h"

#include <cmath>
#include <filesystem>
#include <utility>

#include "core/units.h"
#include "engine/study_files/model_overrides.h"
#include "model_files/seeker_geometry.h"

namespace poise::model_files {
using namespace poise::engine;
namespace {

using units::kAngle;
using units::kLength;

struct SourceDef {
  const char* name;
  double default_order;
  bool load_scaled;
};
// The paper's run-out terms (Sec. 2.1.1 (3)) are scaled by k'; its random wobble terms
// (Sec. 2.1.1 (4)) are not. Default orders: inner-ring eccentricity and face wobble turn
// with the shaft (1), clearance sets a static offset (0), an oval bore and seat give 2,
// ball form error is taken at the cage's ball-pass order (3 by default; set `order`).
constexpr SourceDef kBearingSources[] = {
    {"radial_runout", 1.0, true},  {"face_runout", 1.0, true},     {"clearance", 0.0, true},
    {"bore_roundness", 2.0, true}, {"ball_roundness", 3.0, false}, {"seat_deformation", 2.0, false},
};

// [yaw.perpendicularity] direction, sigma_of, azimuth (the reading of the tolerance).
void read_tilt_reading(TomlReader& axis_table, const std::string& axis, TiltReading& r) {
  TomlReader t = axis_table.table("perpendicularity");
  if (axis != "yaw") {
    for (const char* key : {"direction", "sigma_of", "azimuth"}) {
      if (t.has(key)) {
        t.error(key, "",
                std::string("no `") + key +
                    "` here: the pitch axis' perpendicularity is its tilt towards "
                    "the yaw axis, one direction by definition (the key belongs to [yaw.perpendicularity])");
      }
    }
    return;
  }
  const std::string direction = t.choice("direction", {"random", "fixed"}, "random");
  r.random_direction = direction == "random";
  // With a fixed direction the tolerance is that of the one signed component: sigma_of may
  // say "component" (so that one override of `direction` and one of `sigma_of` turn the
  // shipped reading into the paper's), never "magnitude".
  const std::string sigma_of =
      t.choice("sigma_of", {"magnitude", "component"}, r.random_direction ? "magnitude" : "component");
  r.per_component = r.random_direction && sigma_of == "component";
  if (!r.random_direction || t.schema_only()) r.azimuth = t.quantity("azimuth", kAngle, {}, 0.0);
  if (r.random_direction && t.has("azimuth")) {
    t.error("azimuth", "",
            "no azimuth with direction = \"random\" (the azimuth is drawn); set direction = "
            "\"fixed\" to give one");
  }
  if (!r.random_direction && sigma_of == "magnitude") {
    t.error("sigma_of", sigma_of,
            "sigma_of = \"component\" (or no sigma_of) with direction = \"fixed\": the "
            "tolerance is that of the one signed component along `azimuth`; \"magnitude\" reads a tilt of random "
            "direction");
  }
}

SeekerAxis read_axis(TomlReader& root, const std::string& name) {
  SeekerAxis axis;
  TomlReader t = root.table(name);
  axis.span = t.quantity("bearing_span", kLength, positive);
  t.string("span_source", "");
  axis.perpendicularity = read_tolerance(t, "perpendicularity", kLength, "mm");
  read_tilt_reading(t, name, axis.tilt_reading);
  for (const auto& def : kBearingSources) {
    if (!t.has_or_schema(def.name)) continue;
    BearingSource src;
    src.name = def.name;
    src.load_scaled = def.load_scaled;
    src.spec = read_tolerance(t, def.name, kLength, "mm");
    TomlReader st = t.table(def.name);
    src.order = st.number(
        "order", [](double v) { return v >= 0 ? "" : "an order >= 0"; }, def.default_order);
    axis.bearing_sources.push_back(src);
  }
  return axis;
}

}  // namespace

std::string TiltReading::describe() const {
  if (!random_direction) return "fixed direction (azimuth " + units::format(azimuth, "deg") + "), signed tolerance";
  return per_component ? "random direction, tolerance per component (x and y drawn independently)"
                       : "random direction, tolerance of the magnitude (each component sigma/sqrt 2)";
}

std::vector<std::string> SeekerModel::tolerance_keys() const {
  std::vector<std::string> keys = {"yaw.perpendicularity"};
  for (const auto& src : yaw.bearing_sources) keys.push_back("yaw." + src.name);
  keys.emplace_back("pitch.perpendicularity");
  for (const auto& src : pitch.bearing_sources) keys.push_back("pitch." + src.name);
  keys.emplace_back("optics.axis_error");
  return keys;
}

models::WangBudgetInputs SeekerModel::budget_inputs() const {
  models::WangBudgetInputs in;
  auto axis_in = [](const SeekerAxis& a) {
    models::WangBudgetAxisInputs x;
    x.span = a.span;
    x.perpendicularity = a.perpendicularity.tolerance;
    for (const auto& s : a.bearing_sources) {
      if (s.name == "radial_runout") x.radial_runout = s.spec.tolerance;
      if (s.name == "face_runout") x.face_runout = s.spec.tolerance;
      if (s.name == "clearance") x.clearance = s.spec.tolerance;
      if (s.name == "bore_roundness") x.bore_roundness = s.spec.tolerance;
      if (s.name == "ball_roundness") x.ball_roundness = s.spec.tolerance;
      if (s.name == "seat_deformation") x.seat_deformation = s.spec.tolerance;
    }
    return x;
  };
  in.yaw = axis_in(yaw);
  in.pitch = axis_in(pitch);
  in.k_min = load_deformation.dist.lower();
  in.k_max = load_deformation.dist.upper();
  in.optical_axis_error = optical_axis.tolerance;
  in.barrel_length = barrel_length;
  in.alpha_min = yaw_min;
  in.alpha_max = yaw_max;
  in.beta_min = pitch_min;
  in.beta_max = pitch_max;
  in.pixel_ifov = pixel_ifov;
  return in;
}

SeekerModel load_seeker_model(const std::string& path, const std::map<std::string, std::string>& overrides) {
  auto [doc, ctx] = open_model_file(path, overrides);
  TomlReader root(doc, ctx);
  SeekerModel m;
  static_cast<ModelHeader&>(m) = read_model_header(root, "seeker_two_axis");
  {
    TomlReader t = root.table("field_of_regard");
    m.yaw_min = t.quantity("yaw_min", kAngle);
    m.yaw_max = t.quantity("yaw_max", kAngle);
    m.pitch_min = t.quantity("pitch_min", kAngle);
    m.pitch_max = t.quantity("pitch_max", kAngle);
    const double lim = 89.0 * units::kRadPerDeg;
    if (m.yaw_max < m.yaw_min) t.error("yaw_max", "", "yaw_max >= yaw_min");
    if (m.pitch_max < m.pitch_min) t.error("pitch_max", "", "pitch_max >= pitch_min");
    if (std::abs(m.pitch_min) > lim || std::abs(m.pitch_max) > lim) {
      t.error("pitch_max", "", "pitch angles within +-89 deg (the yaw error grows as tan(pitch))");
    }
    m.pixel_ifov = t.quantity("pixel_ifov", kAngle, positive);
    m.pixel_ifov_source = t.string("pixel_ifov_source", "");
  }
  m.load_deformation = read_tolerance(root, "load_deformation", units::kDimensionless, "");
  if (m.load_deformation.dist.lower() < 0) {
    root.table("load_deformation").error("min", "", "a load-deformation factor k' >= 0");
  }
  m.yaw = read_axis(root, "yaw");
  m.pitch = read_axis(root, "pitch");
  {
    TomlReader t = root.table("optics");
    m.barrel_length = t.quantity("barrel_length", kLength, positive);
    m.optical_axis = read_tolerance(t, "axis_error", kLength, "mm");
  }
  m.geometry = read_seeker_geometry(root, m.yaw.span, m.pitch.span, std::filesystem::path(path).parent_path().string(),
                                    m.meshes);
  finish(doc, *ctx);
  if (!ctx->errors.empty()) throw ValidationError(ctx->errors);
  return m;
}

SeekerSampler::SeekerSampler(SeekerModel model) : model_(std::move(model)) {
  // Each column with the model file's tolerance key it is drawn from (its Sobol group).
  std::string tolerance;
  auto add = [&](std::string name, const char* unit, double factor) {
    columns_.push_back({std::move(name), unit, factor});
    column_tolerances_.push_back(tolerance);
  };
  tolerance = "load_deformation";
  add("k_load", "1", 1.0);
  tolerance = "yaw.perpendicularity";
  if (model_.yaw.tilt_reading.per_component && model_.yaw.tilt_reading.random_direction) {
    add("yaw_perpendicularity_x_arcsec", "arcsec", units::kRadPerArcsec);
    add("yaw_perpendicularity_y_arcsec", "arcsec", units::kRadPerArcsec);
  } else {
    add("yaw_perpendicularity_tilt_arcsec", "arcsec", units::kRadPerArcsec);
    add("yaw_perpendicularity_azimuth_deg", "deg", units::kRadPerDeg);
  }
  tolerance = "pitch.perpendicularity";
  add("pitch_perpendicularity_arcsec", "arcsec", units::kRadPerArcsec);
  tolerance = "optics.axis_error";
  add("optics_collimation_arcsec", "arcsec", units::kRadPerArcsec);
  for (const auto* axis : {"yaw", "pitch"}) {
    const SeekerAxis& a = std::string(axis) == "yaw" ? model_.yaw : model_.pitch;
    for (const auto& s : a.bearing_sources) {
      tolerance = std::string(axis) + "." + s.name;
      for (const char* bearing : {"A", "B"}) {
        add(std::string(axis) + "_" + s.name + "_" + bearing + "_um", "um", 1e-6);
        add(std::string(axis) + "_" + s.name + "_" + bearing + "_phase_deg", "deg", units::kRadPerDeg);
      }
    }
  }
}

models::SeekerErrorState SeekerSampler::draw(std::span<const double> u, std::span<double> values) const {
  if (u.size() != dimension() || values.size() != dimension()) {  // per sample: no string unless wrong
    throw Error("seeker sampler: design point of the wrong size");
  }
  std::size_t k = 0;
  // Drawn values go to `values` in SI first, converted to display units at the end.
  auto take = [&](double v) { values[k++] = v; };
  take(model_.load_deformation.dist.quantile(u[k]));
  // Yaw axis perpendicularity over the span, read as the model says (two design dimensions
  // in every reading, so the other inputs keep their draws).
  const TiltReading& reading = model_.yaw.tilt_reading;
  const sampling::Distribution& perp = model_.yaw.perpendicularity.dist;
  const double span = model_.yaw.span;
  if (!reading.random_direction) {  // signed, along the stated azimuth; the second dimension unused
    take(perp.quantile(u[k]) / span);
    take(reading.azimuth);
  } else if (reading.per_component) {
    take(perp.quantile(u[k]) / span);
    take(perp.quantile(u[k]) / span);
  } else {  // the magnitude towards a uniformly random azimuth
    take(perp.magnitude_quantile(u[k]) / span);
    take(2.0 * units::kPi * u[k]);
  }
  take(model_.pitch.perpendicularity.dist.quantile(u[k]) / model_.pitch.span);
  take(model_.optical_axis.dist.quantile(u[k]) / model_.barrel_length);
  for (int axis = 0; axis < 2; ++axis) {
    const SeekerAxis& a = axis == 0 ? model_.yaw : model_.pitch;
    for (const auto& src : a.bearing_sources) {
      for (int bearing = 0; bearing < 2; ++bearing) {
        take(src.spec.dist.magnitude_quantile(u[k]));
        take(2.0 * units::kPi * u[k]);
      }
    }
  }
  const models::SeekerErrorState s = state_of(values);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] /= columns_[i].display_factor;
  return s;
}

models::SeekerErrorState SeekerSampler::state_of(std::span<const double> si) const {
  if (si.size() != dimension()) throw Error("seeker sampler: input values of the wrong size");
  models::SeekerErrorState s;
  const double k_load = si[0];
  const TiltReading& reading = model_.yaw.tilt_reading;
  if (reading.random_direction && reading.per_component) {
    s.yaw.static_tilt = {si[1], si[2]};
  } else {  // a tilt towards an azimuth
    s.yaw.static_tilt = {si[1] * std::cos(si[2]), si[1] * std::sin(si[2])};
  }
  s.pitch.static_tilt = {0.0, si[3]};
  s.collimation = si[4];
  std::size_t k = 5;
  for (int axis = 0; axis < 2; ++axis) {
    const SeekerAxis& a = axis == 0 ? model_.yaw : model_.pitch;
    models::AxisErrorState& st = axis == 0 ? s.yaw : s.pitch;
    for (const auto& src : a.bearing_sources) {
      const double scale = (src.load_scaled ? k_load : 1.0) / a.span;
      for (double sign : {-1.0, +1.0}) {  // bearing A at -L/2, bearing B at +L/2
        const double amp = si[k++];
        const double phase = si[k++];
        st.add({sign * scale * amp, src.order, phase});
      }
    }
  }
  return s;
}

std::vector<double> SeekerSampler::nominal() const {
  std::vector<double> si(dimension(), 0.0);
  si[0] = model_.load_deformation.dist.quantile(0.5);
  const TiltReading& reading = model_.yaw.tilt_reading;
  if (!reading.random_direction) si[2] = reading.azimuth;
  for (std::size_t i = 0; i < si.size(); ++i) si[i] /= columns_[i].display_factor;
  return si;
}

}  // namespace poise::model_files
