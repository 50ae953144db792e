#include "kinds/seeker_los/seeker_los_study.h"

#include <algorithm>
#include <cmath>

#include "core/units.h"
#include <tbb/parallel_invoke.h>

#include "engine/convergence.h"
#include "engine/sample_driver.h"
#include "kinds/seeker_los/seeker_los_sections.h"

namespace poise::studies {
namespace {
constexpr double kArcsec = units::kArcsecPerRad;
// Above this many stored grid values (4 bytes each) the pooled statistics and maps use
// the first samples only, so memory stays bounded (~400 MB).
constexpr std::size_t kMaxStoredGridValues = 100'000'000;
}  // namespace

SeekerLosStudy::SeekerLosStudy(StudyConfig config, SeekerModel model, std::size_t samples,
                               std::uint64_t seed)
    : config_(std::move(config)),
      model_(std::move(model)),
      sampler_(model_),
      samples_(samples),
      seed_(seed),
      design_(make_design(config_, seed, samples, sampler_.dimension())),
      grid_(models::linspace(model_.yaw_min, model_.yaw_max, seeker_sections(config_).yaw_points),
            models::linspace(model_.pitch_min, model_.pitch_max, seeker_sections(config_).pitch_points)),
      requirement_rad_(seeker_sections(config_).requirement_in_pixels ? seeker_sections(config_).requirement * model_.pixel_ifov
                                                     : seeker_sections(config_).requirement) {}

SeekerLosStudy::Workspace SeekerLosStudy::make_workspace() const {
  Workspace ws;
  ws.u.resize(sampler_.dimension());
  ws.grid = grid_.make_workspace();
  ws.errors.resize(grid_.size());
  return ws;
}

void SeekerLosStudy::compute(std::size_t i, Workspace& ws, SeekerSampleResult& out) const {
  out.index = i;
  out.ok = true;
  out.message.clear();
  out.inputs.assign(sampler_.dimension(), NAN);
  out.outputs.assign(kNumSeekerOutputs, NAN);
  out.grid_total_arcsec.assign(grid_.size(), NAN);
  try {
    design_.point(i, ws.u);
    const models::SeekerErrorState state = sampler_.draw(ws.u, out.inputs);
    grid_.evaluate(state, ws.grid, ws.errors);
    double max_total = 0, sum_sq = 0, max_yaw = 0, max_pitch = 0;
    std::size_t ok_points = 0;
    for (std::size_t g = 0; g < ws.errors.size(); ++g) {
      const auto& e = ws.errors[g];
      if (!std::isfinite(e.total) || !std::isfinite(e.yaw) || !std::isfinite(e.pitch)) {
        throw Error("non-finite pointing error at grid point " + std::to_string(g));
      }
      max_total = std::max(max_total, e.total);
      sum_sq += e.total * e.total;
      max_yaw = std::max(max_yaw, std::abs(e.yaw));
      max_pitch = std::max(max_pitch, std::abs(e.pitch));
      ok_points += e.total <= requirement_rad_ ? 1 : 0;
      out.grid_total_arcsec[g] = static_cast<float>(e.total * kArcsec);
    }
    const double n = static_cast<double>(ws.errors.size());
    out.outputs = {max_total * kArcsec,
                   std::sqrt(sum_sq / n) * kArcsec,
                   max_yaw * kArcsec,
                   max_pitch * kArcsec,
                   max_total / model_.pixel_ifov,
                   static_cast<double>(ok_points) / n,
                   max_yaw / model_.pixel_ifov,
                   max_pitch / model_.pixel_ifov};
  } catch (const std::exception& e) {
    out.ok = false;
    out.message = e.what();
  }
}

std::vector<models::PointingError> SeekerLosStudy::grid_errors(std::size_t i) const {
  Workspace ws = make_workspace();
  design_.point(i, ws.u);
  std::vector<double> values(sampler_.dimension());
  grid_.evaluate(sampler_.draw(ws.u, values), ws.grid, ws.errors);
  return ws.errors;
}

namespace {
void encode_seeker(const SeekerSampleResult& r, ByteWriter& w) {
  encode_sample_fields(r, w);
  w.put_vector(r.grid_total_arcsec);
}
void decode_seeker(ByteReader& rd, SeekerSampleResult& r) {
  decode_sample_fields(rd, r);
  rd.get_vector(r.grid_total_arcsec);
}
}  // namespace

SeekerMcResult SeekerLosStudy::run(
    int threads, bool progress,
    const std::function<void(std::span<const SeekerSampleResult>)>& sink, const SeekerRunControl& control) const {
  SeekerMcResult r;
  r.n = samples_;
  const std::size_t g = grid_.size();
  const std::size_t stored = std::min(samples_, std::max<std::size_t>(1, kMaxStoredGridValues / g));
  std::vector<float> grid_values;  // [sample][grid point], ok samples only
  grid_values.reserve(stored * g);
  std::vector<std::vector<double>> out_values(kNumSeekerOutputs);
  std::size_t n_ok = 0, n_all_ok = 0;

  sampling::Progress bar("samples", samples_, progress && (!control.distributed || sampling::Cluster::root()));
  DriveSpec spec{0, samples_, config_.block, 16, threads, control.distributed};
  const DriveOutcome outcome = drive_samples<SeekerSampleResult>(
      spec, [this] { return make_workspace(); },
      [this](std::size_t i, Workspace& ws, SeekerSampleResult& res) { compute(i, ws, res); },
      [&](std::size_t, std::span<const SeekerSampleResult> block) {
        if (sink) sink(block);
        for (const auto& s : block) {
          if (!s.ok) {
            ++r.failures;
            if (r.failed.size() < 100) r.failed.emplace_back(s.index, s.message);
            continue;
          }
          ++n_ok;
          r.ok_index.push_back(s.index);
          for (std::size_t k = 0; k < kNumSeekerOutputs; ++k) out_values[k].push_back(s.outputs[k]);
          if (s.outputs[0] <= requirement_rad_ * kArcsec) ++n_all_ok;
          if (grid_values.size() < stored * g) {
            grid_values.insert(grid_values.end(), s.grid_total_arcsec.begin(),
                               s.grid_total_arcsec.end());
          }
        }
      },
      [&](std::size_t completed) {
        return control.stop ? control.stop(out_values, r.ok_index, r.failures, completed) : std::string();
      },
      encode_seeker, decode_seeker, &bar);
  bar.finish();
  r.wall_seconds = bar.elapsed_seconds();
  r.completed = outcome.completed;
  r.interrupted = outcome.interrupted;
  r.signal = outcome.signal;
  r.stop_reason = outcome.stop_reason;
  if (n_ok == 0) return r;
  for (auto& v : out_values) r.outputs.push_back(summarize_output(v, r.ok_index, config_.replicate_size));
  r.fraction_samples_ok = sampling::fraction_wilson(n_all_ok, n_ok);
  const auto& field = r.outputs[5];
  r.fraction_field_ok = field.mean;
  // The tail runs on the same threads: the pooled summary beside the per-point maps.
  const std::size_t rows = grid_values.size() / g;
  r.map_p50.resize(g);
  r.map_p95.resize(g);
  r.map_p99_73.resize(g);
  tbb::task_arena arena(std::max(1, threads));
  arena.execute([&] {
    tbb::parallel_invoke(
        [&] {
          const std::vector<double> pooled(grid_values.begin(), grid_values.end());
          r.pooled = sampling::summarize(pooled);
        },
        [&] {
          tbb::parallel_for(std::size_t{0}, g, [&](std::size_t p) {
            std::vector<double> column(rows);
            for (std::size_t k = 0; k < rows; ++k) column[k] = grid_values[k * g + p];
            r.map_p50[p] = sampling::quantile_value(column, 0.5);
            r.map_p95[p] = sampling::quantile_value(column, 0.95);
            r.map_p99_73[p] = sampling::quantile_value(column, 0.9973);
          });
        });
  });
  r.los_max_sorted = out_values[0];
  std::sort(r.los_max_sorted.begin(), r.los_max_sorted.end());
  r.values = std::move(out_values);
  return r;
}

}  // namespace poise::studies
