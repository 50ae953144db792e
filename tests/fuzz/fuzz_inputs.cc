// libFuzzer target for every input file Poise reads (issues 9 and 20, "Bad input").
//
// The first input byte selects what is fuzzed; the rest is the file text:
//   0  a study file, through validate_study() (what `poise validate` does)
//   1  a seeker model file          (load_seeker_model)
//   2  a gimbal model file          (load_gimbal_model)
//   3  a balancing-machine model    (load_balancing_model)
//   4  a platform model             (load_platform_model)
//   5  a simulator-disk model       (load_disk_geometry_model)
//   6  a quantity "<number> <unit>" (units::parse_quantity, parse_as, unit_factor, format)
//   7  a study file and a model file, split at the line "#---model---"; the model is written
//      next to the study as fuzz_model.toml (reference it with model = "fuzz_model.toml")
//   c  a torque CSV (`poise fit` and `poise diagnose`: read, sine fit, residual diagnosis)
//   r  a raw record (`poise diagnose-record`): first line the --kt value, then the CSV
//   o  an OBJ mesh, s  an STL mesh (ASCII or binary): a user's CAD part (load, checks, mass
//      properties by the divergence theorem and by Embree ray casting)
//   p  an optimization file (load_optimization, with its base study)
//   b  a budget file (load_budget, then check_budget: the whole `poise budget` recomputation)
// Any other byte selects byte % 8 of the first eight. The kinds beyond the TOML study and
// model files are in fuzz_data_inputs.cc and fuzz_plan_inputs.cc.
// Files are written to a private temporary folder laid out like the repository: the study
// goes to <tmp>/studies/, which also holds links to the repository's studies, and
// <tmp>/models links to the repository's models/, so "../models/x.toml" resolves.
//
// Refusals are expected: poise::Error (ValidationError included) and a few standard
// exceptions with a clear message. Crashes, sanitizer reports, hangs, memory blow-ups and
// any other exception are findings: the target aborts with the exception's type and text.
//
// With POISE_FUZZ_WRITE_SEEDS=<dir> set, the program writes the seed corpus (the repository's
// studies, models, data, meshes and tests/data/malformed, each with its selector byte) to
// <dir> and exits; POISE_FUZZ_SEED_SELECTORS=<bytes> keeps the seeds of those selectors only
// (one ctest test per input kind).
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <ios>
#include <sstream>
#include <string>
#include <string_view>
#include <typeinfo>

#include "core/error.h"
#include "core/units.h"
#include "kinds/balancing_machine/balancing_model.h"
#include "model_files/disk_geometry_model.h"
#include "model_files/gimbal_model.h"
#include "kinds/platform_balancing/platform_model.h"
#include "model_files/seeker_model.h"
#include "engine/run/study_runner.h"
#include "engine/study_files/toml_reader.h"
#include "kinds/registry.h"
#include "fuzz_common.h"

using namespace poise::kinds::balancing_machine;  // the kinds' and model files' own namespaces
using namespace poise::kinds::platform_balancing;  // the kinds' and model files' own namespaces
using namespace poise::model_files;  // the kinds' and model files' own namespaces

namespace poise::fuzz {

namespace {
fs::path g_dir;  // private temporary folder
}  // namespace

const fs::path& work_dir() { return g_dir; }

void write_file(const fs::path& path, std::string_view text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace poise::fuzz

namespace {

using namespace poise::fuzz;
constexpr std::string_view kModelSeparator = "\n#---model---\n";
std::string g_seed_selectors;  // POISE_FUZZ_SEED_SELECTORS ("" = all)
fs::path g_seed_dir;
int g_seed_count = 0;

void add_seed(char selector, const std::string& text) {
  if (!g_seed_selectors.empty() && g_seed_selectors.find(selector) == std::string::npos) return;
  write_file(g_seed_dir / ("seed_" + std::to_string(g_seed_count++)), std::string(1, selector) + text);
}

// Selector of a model file by its [model] kind.
char model_selector(const std::string& text) {
  if (text.find("\"gimbal_static_unbalance\"") != std::string::npos) return '2';
  if (text.find("\"balancing_machine\"") != std::string::npos) return '3';
  if (text.find("\"platform_three_gimbal\"") != std::string::npos) return '4';
  if (text.find("\"simulator_disk\"") != std::string::npos) return '5';
  return '1';
}

void write_seeds(const fs::path& out) {
  fs::create_directories(out);
  g_seed_dir = out;
  const AddSeed add = add_seed;
  for (const auto& e : fs::directory_iterator(kSource / "studies")) {
    if (e.path().extension() == ".toml") add('0', read_file(e.path()));
  }
  for (const auto& e : fs::directory_iterator(kSource / "models")) {
    if (e.path().extension() != ".toml") continue;
    const std::string text = read_file(e.path());
    add(model_selector(text), text);
    // The same model beside a study that uses it (selector 7).
    add('7', "[study]\nname = \"s\"\nkind = \"seeker_los\"\nmodel = \"fuzz_model.toml\"\n"
             "[sampling]\nmethod = \"sobol\"\nsamples = 8\nseed = 1\n[grid]\nyaw_points = 3\n"
             "pitch_points = 3\n[requirement]\nlos_error = \"1 px\"" +
                 std::string(kModelSeparator) + text);
  }
  const fs::path malformed = kSource / "tests/data/malformed";
  if (fs::is_directory(malformed)) {
    for (const auto& e : fs::recursive_directory_iterator(malformed)) {
      if (!e.is_regular_file() || e.path().extension() == ".md") continue;
      const std::string text = read_file(e.path());
      const bool model = e.path().parent_path().filename() == "models";
      add(model ? model_selector(text) : '0', text);
    }
  }
  for (const char* q : {"82 mm", "0.004 mm", "30 deg", "4 arcsec", "12.91 mN*m", "1e-3 kg*m^2", "3000 r/min",
                        "9.81 m/s^2", "200 GPa", "1 px", "5 %", "0.5 N*m/A", "1e308 km", "1 m^13", "nan mm"}) {
    add('6', q);
  }
  seed_data_inputs(add);
  seed_plan_inputs(add);
  std::printf("wrote %d seeds to %s\n", g_seed_count, out.c_str());
}

// Exceptions a user may see: poise's own, and standard ones whose message says what is wrong.
bool acceptable(const std::exception& e) {
  if (dynamic_cast<const poise::Error*>(&e)) return true;
  if (dynamic_cast<const fs::filesystem_error*>(&e)) return true;  // "filesystem error: ... [path]"
  return false;
}

[[noreturn]] void finding(const char* type, const char* what) {
  std::fprintf(stderr, "\nFUZZ FINDING: uncaught exception of type %s: %s\n", type, what);
  std::fflush(stderr);
  std::abort();
}

void fuzz_units(std::string_view text) {
  using namespace poise::units;
  try {
    const Quantity q = parse_quantity(text);
    (void)dimension_name(q.dim);
    (void)example_unit(q.dim);
  } catch (const poise::Error&) {
  }
  for (const Dimension& d : {kDimensionless, kLength, kAngle, kTorque, kPressure, kAcceleration}) {
    try {
      (void)parse_as(text, d);
    } catch (const poise::Error&) {
    }
  }
  // The text as a unit alone (the part after the number).
  try {
    (void)unit_factor(text);
    (void)format(1.5, text);
  } catch (const poise::Error&) {
  }
}

void run_one(std::uint8_t byte, std::string_view text) {
  switch (byte) {
    case 'c': fuzz_torque_csv(text); return;
    case 'r': fuzz_record(text); return;
    case 'o': fuzz_mesh(text, ".obj"); return;
    case 's': fuzz_mesh(text, ".stl"); return;
    case 'p': fuzz_optimization(text); return;
    case 'b': fuzz_budget(text); return;
    default: break;
  }
  const unsigned selector = byte % 8u;
  using namespace poise::engine;
  const fs::path study = g_dir / "studies" / "fuzz_study.toml";
  const fs::path model = g_dir / "studies" / "fuzz_model.toml";
  switch (selector) {
    case 0:
      write_file(study, text);
      (void)validate_study(study.string());
      break;
    case 7: {
      const auto split = text.find(kModelSeparator);
      write_file(study, text.substr(0, split));
      write_file(model, split == std::string_view::npos ? std::string_view() : text.substr(split + kModelSeparator.size()));
      (void)validate_study(study.string());
      break;
    }
    case 1:
      write_file(model, text);
      (void)load_seeker_model(model.string());
      break;
    case 2:
      write_file(model, text);
      (void)load_gimbal_model(model.string());
      break;
    case 3:
      write_file(model, text);
      (void)load_balancing_model(model.string());
      break;
    case 4:
      write_file(model, text);
      (void)load_platform_model(model.string());
      break;
    case 5:
      write_file(model, text);
      (void)load_disk_geometry_model(model.string());
      break;
    default:
      fuzz_units(text);
      break;
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  poise::kinds::register_study_kinds();
  if (const char* seeds = std::getenv("POISE_FUZZ_WRITE_SEEDS")) {
    if (const char* only = std::getenv("POISE_FUZZ_SEED_SELECTORS")) g_seed_selectors = only;
    write_seeds(seeds);
    std::exit(0);
  }
  char templ[] = "/tmp/poise_fuzz_XXXXXX";
  if (!::mkdtemp(templ)) {
    std::perror("mkdtemp");
    std::abort();
  }
  g_dir = templ;
  fs::create_directories(g_dir / "studies");
  fs::create_directory_symlink(kSource / "models", g_dir / "models");
  for (const auto& e : fs::directory_iterator(kSource / "studies")) {
    fs::create_symlink(e.path(), g_dir / "studies" / e.path().filename());
  }
  // Removed at exit (also after a finding's abort the folder is small and in /tmp).
  std::atexit([] {
    std::error_code ec;
    fs::remove_all(g_dir, ec);
  });
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::string_view text(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    run_one(data[0], text);
  } catch (const std::exception& e) {
    if (!acceptable(e)) finding(typeid(e).name(), e.what());
  } catch (...) {
    finding("(not a std::exception)", "");
  }
  return 0;
}
