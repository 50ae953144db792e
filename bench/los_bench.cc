/// Benchmarks of the seeker LOS study (Google Benchmark 1.7.1).
///
///   BM_LosGridEvaluation   LosGrid::evaluate of realistic error states on the study's
///                          13 x 13 grid over +-30 deg (factorized chain).
///                          Target: >= 10 million gimbal-angle evaluations/s per core.
///   BM_LosSinglePoint      los_direction + pointing_error at one (alpha, beta) from
///                          scratch (both frames rebuilt, no factorization).
///   BM_SampleCompute       SeekerLosStudy::compute: design point + draw + grid + outputs.
///   BM_StudyRun/threads:N  SeekerLosStudy::run on N threads, 8192 samples, no sink: the
///                          samples, their grid values gathered column by column (kept in
///                          memory: no file is written for a run without samples.h5), the
///                          field statistics and the summaries (the tail). Target: >= 1.85x
///                          samples/s from 1 to 2 threads (issue 19).
///   BM_StudyComputeOnly/threads:N  diagnostic: the parallel part of run() alone.
///
/// The study and model are the project defaults (studies/los_seeker_wang2011.toml and the
/// model it names), loaded once per process outside every timed loop. The source tree is
/// found from $POISE_SOURCE_DIR if set, else from this file's own path (bench/..).
///
/// Run: poise_bench --benchmark_min_time=0.5
#include <benchmark/benchmark.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <span>
#include <utility>
#include <vector>

#include "models/seeker_los_chain.h"
#include "sampling/design.h"
#include "engine/run/sample_driver.h"
#include "kinds/registry.h"
#include "kinds/seeker_los/seeker_los_study.h"
#include "model_files/seeker_model.h"
#include "engine/study_files/study_config.h"

using namespace poise::kinds::seeker_los;  // the kinds' and model files' own namespaces
using namespace poise::model_files;  // the kinds' and model files' own namespaces

namespace {

namespace fs = std::filesystem;
using poise::models::LosGrid;
using poise::models::PointingError;
using poise::models::SeekerErrorState;
using poise::kinds::seeker_los::SeekerLosStudy;
using SeekerSampleResult = poise::engine::SampleResult;

constexpr std::size_t kRunSamples = 8192;  // samples per BM_StudyRun iteration

// Root of the source tree: $POISE_SOURCE_DIR, else the parent of this file's folder
// (CMake compiles with absolute source paths, so __FILE__ is absolute).
fs::path source_dir() {
  if (const char* env = std::getenv("POISE_SOURCE_DIR"); env != nullptr && *env != '\0') {
    return fs::path(env);
  }
  return fs::path(__FILE__).parent_path().parent_path();
}

// Everything the benchmarks share, built once on first use (never inside a timed loop).
struct Setup {
  SeekerLosStudy study;
  // Realistic draws of every error of the Wang model (6 bearing sources x 2 bearings per
  // axis = 12 tilt harmonics per axis, plus static tilts and collimation): the design
  // points of the study's first kStates samples mapped through its sampler.
  static constexpr std::size_t kStates = 256;
  std::vector<SeekerErrorState> states;

  static SeekerLosStudy make_study() {
    poise::kinds::register_study_kinds();  // as the CLI does: load_study checks the kind by name
    const fs::path study_file = source_dir() / "studies" / "los_seeker_wang2011.toml";
    poise::engine::StudyConfig cfg = poise::engine::load_study(study_file.string());
    // As the study runner does: the study's own [overrides] apply to the model.
    poise::model_files::SeekerModel model =
        poise::model_files::load_seeker_model(cfg.model_path, cfg.overrides);
    const std::uint64_t seed = cfg.seed;
    return SeekerLosStudy(std::move(cfg), std::move(model), kRunSamples, seed);
  }

  Setup() : study(make_study()) {
    const auto& sampler = study.sampler();
    const poise::sampling::Design design(study.config().method, study.seed(), kStates,
                                         sampler.dimension());
    std::vector<double> u(sampler.dimension()), values(sampler.dimension());
    for (std::size_t i = 0; i < kStates; ++i) {
      design.point(i, u);
      states.push_back(sampler.draw(u, values));
    }
  }
};

const Setup& setup() {
  static const Setup s;  // thread-safe lazy init; the first benchmark pays it untimed
  return s;
}

// Items-per-second counter under the given name (rate over the benchmark's time).
void rate(benchmark::State& state, const char* name, std::size_t items_per_iteration) {
  state.counters[name] = benchmark::Counter(
      static_cast<double>(state.iterations()) * static_cast<double>(items_per_iteration),
      benchmark::Counter::kIsRate);
}

// 1. The factorized grid: 13 yaw frames + 13 pitch LOS, then one 3x3 product and the
//    error extraction per grid point. states:1 evaluates one error state over and over
//    (branch predictors learn its libm paths); states:256 cycles through 256 draws, as
//    a Monte Carlo run does, and is the realistic figure (~25% fewer evals/s).
void BM_LosGridEvaluation(benchmark::State& state) {
  const Setup& s = setup();
  const LosGrid& grid = s.study.grid();
  const auto n_states = static_cast<std::size_t>(state.range(0));
  LosGrid::Workspace ws = grid.make_workspace();
  std::vector<PointingError> out(grid.size());
  std::size_t k = 0;
  for (auto _ : state) {
    grid.evaluate(s.states[k], ws, out);
    k = k + 1 == n_states ? 0 : k + 1;
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  rate(state, "evals_per_s", grid.size());
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * grid.size()));
  state.counters["harmonics"] =  // yaw + pitch, of the first state
      static_cast<double>(s.states[0].yaw.n_harmonics + s.states[0].pitch.n_harmonics);
}
BENCHMARK(BM_LosGridEvaluation)->ArgName("states")->Arg(1)->Arg(Setup::kStates);

// 2. One gimbal angle from scratch: both frames (with their harmonic sums) rebuilt per
//    point. Cycles through the grid's angles so the inputs vary between iterations.
void BM_LosSinglePoint(benchmark::State& state) {
  const Setup& s = setup();
  const LosGrid& grid = s.study.grid();
  std::vector<std::pair<double, double>> angles;
  for (double a : grid.alpha()) {
    for (double b : grid.beta()) angles.emplace_back(a, b);
  }
  std::size_t k = 0;
  for (auto _ : state) {
    const auto [alpha, beta] = angles[k];
    k = k + 1 == angles.size() ? 0 : k + 1;
    const Eigen::Vector3d d = poise::models::los_direction(s.states[0], alpha, beta);
    PointingError e = poise::models::pointing_error(d, alpha, beta);
    benchmark::DoNotOptimize(e);
  }
  rate(state, "evals_per_s", 1);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_LosSinglePoint);

// 3. One whole sample as the parallel runner computes it, consecutive indices.
void BM_SampleCompute(benchmark::State& state) {
  const SeekerLosStudy& study = setup().study;
  SeekerLosStudy::Workspace ws = study.make_workspace();
  SeekerSampleResult result;
  std::size_t i = 0;
  for (auto _ : state) {
    study.compute(i, ws, result);
    i = i + 1 == study.samples() ? 0 : i + 1;
    benchmark::DoNotOptimize(result.outputs.data());
    benchmark::ClobberMemory();
  }
  if (!result.ok) state.SkipWithError(result.message.c_str());
  rate(state, "samples_per_s", 1);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_SampleCompute);

// 4. The whole run: parallel blocks of StudyConfig::block samples, the in-order
//    aggregation on the calling thread, then the statistics (sorts, quantile maps).
//    Real time, since the work is spread over threads; compare samples_per_s of
//    threads:2 against threads:1 for the speedup.
void BM_StudyRun(benchmark::State& state) {
  const SeekerLosStudy& study = setup().study;
  const int threads = static_cast<int>(state.range(0));
  std::size_t failures = 0;
  for (auto _ : state) {
    // As a run without samples.h5 does ([output] grid_values = false): the grid values kept
    // in memory, the field figures made. A folder is what asks a run for its field.
    poise::engine::RunControl control;
    control.folder = poise::engine::RunFolder{};
    poise::engine::McResult r = study.run(threads, false, {}, {}, control);
    failures += r.failures;
    benchmark::DoNotOptimize(r.outputs.data());
  }
  if (failures != 0) state.SkipWithError("samples failed during the run");
  rate(state, "samples_per_s", study.samples());
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * study.samples()));
  state.counters["block"] = static_cast<double>(study.config().block);
}
BENCHMARK(BM_StudyRun)->ArgName("threads")->Arg(1)->Arg(2)
    ->UseRealTime()->Unit(benchmark::kMillisecond);

// Diagnostic for 4: the parallel part of run() alone (compute() in blocks of
// StudyConfig::block, results dropped), to separate its scaling from the serial tail
// (aggregation, pooled summary and per-grid-point quantile maps) that run() adds.
void BM_StudyComputeOnly(benchmark::State& state) {
  const SeekerLosStudy& study = setup().study;
  const poise::engine::DriveSpec spec{0, study.samples(), study.config().block, 16, static_cast<int>(state.range(0)),
                                       false};
  for (auto _ : state) {
    poise::engine::drive_samples<SeekerSampleResult>(
        spec, [&] { return study.make_workspace(); },
        [&](std::size_t i, SeekerLosStudy::Workspace& ws, SeekerSampleResult& r) {
          study.compute(i, ws, r);
          benchmark::DoNotOptimize(r.outputs.data());
        },
        [](std::span<const SeekerSampleResult>) { return std::string(); },
        [](std::size_t, std::span<const SeekerSampleResult>, std::string_view) {},
        [](std::size_t) { return std::string(); },
        [](const SeekerSampleResult&, poise::engine::ByteWriter&) {},
        [](poise::engine::ByteReader&, SeekerSampleResult&) {});
  }
  rate(state, "samples_per_s", study.samples());
}
BENCHMARK(BM_StudyComputeOnly)->ArgName("threads")->Arg(1)->Arg(2)
    ->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace
