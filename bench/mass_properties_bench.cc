/// Benchmarks of `poise mass-properties` (Google Benchmark 1.7.1), single-threaded code:
///
///   BM_ExactMassProperties   divergence-theorem moments (exact_moments) and the centre of mass,
///                            inertia and principal axes of a 100k-triangle mesh. Target (issue 17
///                            item 5): under 50 ms of CPU per core.
///   BM_MeshCheck             check_mesh() of the same mesh: edges sorted, shells, orientation walk.
///   BM_LoadCheckExact        the command's whole path on that part: binary STL parsed from memory
///                            (vertices welded), checked, exact properties.
/// The mesh: a tube (bore and rim, 12,500-gons) of 100,000 triangles, 60 mm across.
/// Measured (Release, 2 shared cores at load ~9, CPU time, medians of 3): exact properties
/// 1.4-1.9 ms, mesh check 23-33 ms, STL parse + check + exact 27-42 ms: all under the 50 ms.
///
/// Run: poise_mass_properties_bench --benchmark_min_time=0.5
#include <benchmark/benchmark.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "geometry/generators.h"
#include "geometry/mass_properties.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_io.h"
#include "geometry/rigid_body_inertia.h"

namespace {

using namespace poise::geometry;

const Mesh& part() {
  static const Mesh m = tube(0.010, 0.030, 0.0, 0.012, 12500, "tube");
  return m;
}

void BM_ExactMassProperties(benchmark::State& state) {
  const Mesh& m = part();
  double mass = 0.0;
  for (auto _ : state) {
    const MassProperties p = to_mass_properties(exact_moments(m, 2700.0));
    const PrincipalAxes pa = principal_axes(p.inertia);
    mass = p.mass;
    benchmark::DoNotOptimize(pa.moments);
  }
  state.counters["triangles"] = static_cast<double>(m.triangles.size());
  state.counters["mass_g"] = 1e3 * mass;
}
BENCHMARK(BM_ExactMassProperties)->Unit(benchmark::kMillisecond);

void BM_MeshCheck(benchmark::State& state) {
  const Mesh& m = part();
  std::size_t shells = 0;
  for (auto _ : state) {
    const MeshCheck c = check_mesh(m);
    shells = c.shells.size();
    benchmark::DoNotOptimize(shells);
  }
  state.counters["triangles"] = static_cast<double>(m.triangles.size());
  state.counters["shells"] = static_cast<double>(shells);
}
BENCHMARK(BM_MeshCheck)->Unit(benchmark::kMillisecond);

void BM_LoadCheckExact(benchmark::State& state) {
  const std::string path = (std::filesystem::temp_directory_path() / "poise_bench_tube.stl").string();
  write_stl(part(), path, 1e-3);
  std::stringstream ss;
  ss << std::ifstream(path, std::ios::binary).rdbuf();
  const std::string bytes = ss.str();
  std::filesystem::remove(path);
  for (auto _ : state) {
    const Mesh m = read_stl(bytes, "tube.stl", 1e-3);
    require_valid_mesh(m);
    benchmark::DoNotOptimize(to_mass_properties(exact_moments(m, 2700.0)).mass);
  }
  state.counters["bytes"] = static_cast<double>(bytes.size());
}
BENCHMARK(BM_LoadCheckExact)->Unit(benchmark::kMillisecond);

}  // namespace
