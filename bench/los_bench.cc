/// Benchmarks of the seeker LOS study (Google Benchmark 1.7.1).
///
///   BM_LosGridEvaluation   LosGrid::evaluate of one realistic error state on the study's
///                          13 x 13 grid over +-30 deg (factorized chain).
///                          Target: >= 10 million gimbal-angle evaluations/s per core.
///   BM_LosSinglePoint      los_direction + pointing_error at one (alpha, beta) from
///                          scratch (both frames rebuilt, no factorization).
///   BM_SampleCompute       SeekerLosStudy::compute: design point + draw + grid + outputs.
///   BM_StudyRun/threads:N  SeekerLosStudy::run on N threads, 8192 samples, no sink.
///                          Target: >= 1.8x samples/s from 1 to 2 threads.
///
/// The study and model are the project defaults (studies/los_seeker_wang2011.toml and the
/// model it names), loaded once per process outside every timed loop. The source tree is
/// found from $POISE_SOURCE_DIR if set, else from this file's own path (bench/..).
///
/// Run: poise_bench --benchmark_min_time=0.5
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <vector>

#include "models/seeker_los_chain.h"
#include "studies/seeker_los_study.h"
#include "studies/seeker_model.h"
#include "studies/study_config.h"

namespace {

namespace fs = std::filesystem;
using poise::models::LosGrid;
using poise::models::PointingError;
using poise::models::SeekerErrorState;
using poise::studies::SeekerLosStudy;
using poise::studies::SeekerSampleResult;

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
  SeekerErrorState state;  // one realistic draw of every error of the Wang model
  std::size_t harmonics = 0;

  static SeekerLosStudy make_study() {
    const fs::path study_file = source_dir() / "studies" / "los_seeker_wang2011.toml";
    poise::studies::StudyConfig cfg = poise::studies::load_study(study_file.string());
    // As the study runner does: the study's own [overrides] apply to the model.
    poise::studies::SeekerModel model =
        poise::studies::load_seeker_model(cfg.model_path, cfg.overrides);
    const std::uint64_t seed = cfg.seed;
    return SeekerLosStudy(std::move(cfg), std::move(model), kRunSamples, seed);
  }

  Setup() : study(make_study()) {
    // A fixed, well-spread design point (golden-ratio sequence, all in (0, 1)), mapped
    // through the model's sampler like any Monte Carlo sample.
    const auto& sampler = study.sampler();
    std::vector<double> u(sampler.dimension()), values(sampler.dimension());
    for (std::size_t k = 0; k < u.size(); ++k) {
      u[k] = std::fmod(0.5 + std::numbers::phi * static_cast<double>(k + 1), 1.0);
    }
    state = sampler.draw(u, values);
    harmonics = static_cast<std::size_t>(state.yaw.n_harmonics + state.pitch.n_harmonics);
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
//    error extraction per grid point.
void BM_LosGridEvaluation(benchmark::State& state) {
  const Setup& s = setup();
  const LosGrid& grid = s.study.grid();
  LosGrid::Workspace ws = grid.make_workspace();
  std::vector<PointingError> out(grid.size());
  for (auto _ : state) {
    grid.evaluate(s.state, ws, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  rate(state, "evals_per_s", grid.size());
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * grid.size()));
  state.counters["grid_points"] = static_cast<double>(grid.size());
  state.counters["harmonics"] = static_cast<double>(s.harmonics);  // yaw + pitch
}
BENCHMARK(BM_LosGridEvaluation);

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
    const Eigen::Vector3d d = poise::models::los_direction(s.state, alpha, beta);
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
    poise::studies::SeekerMcResult r = study.run(threads, false, {});
    failures += r.failures;
    benchmark::DoNotOptimize(r.outputs.data());
  }
  if (failures != 0) state.SkipWithError("samples failed during the run");
  rate(state, "samples_per_s", study.samples());
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * study.samples()));
  state.counters["block"] = static_cast<double>(study.config().block);
}
BENCHMARK(BM_StudyRun)
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
