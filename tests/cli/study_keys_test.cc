// `poise keys KIND` is generated from the program's own reading of the files: every key the
// shipped study and model files use is in the listing of their kind, and a misspelled key
// gets "did you mean".
#include <gtest/gtest.h>

#include <toml++/toml.h>

#include <filesystem>
#include <set>
#include <string>

#include "engine/study_files/study_keys.h"
#include "engine/kind_interface/study_kind.h"
#include "test_util.h"

namespace poise {
namespace {
namespace fs = std::filesystem;
using test::source_path;

// Every key path of a TOML table in the schema's form ("group[].load[].mass"); free-form
// tables (model overrides, a model's declared budget values) are listed by their name only.
void flatten(const toml::table& t, const std::string& prefix, std::set<std::string>& out) {
  for (const auto& [k, v] : t) {
    const std::string path = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (path == "overrides" || path == "declared") {
      out.insert(path);
      continue;
    }
    if (const auto* sub = v.as_table()) {
      flatten(*sub, path, out);
    } else if (const auto* arr = v.as_array(); arr && arr->is_array_of_tables()) {
      for (const auto& el : *arr) flatten(*el.as_table(), path + "[]", out);
    } else {
      out.insert(path);
    }
  }
}

std::set<std::string> listed(const std::vector<engine::KeyDoc>& keys) {
  std::set<std::string> out;
  for (const auto& k : keys) out.insert(k.path);
  return out;
}

// Whether `key` is listed, itself or with one of its parts a name of the user's own (NAME in
// the listing: a formula model's parameters and their tolerances).
bool is_listed(const std::string& key, const std::set<std::string>& keys) {
  if (keys.count(key)) return true;
  for (std::size_t start = 0; start < key.size();) {
    const std::size_t end = std::min(key.find('.', start), key.size());
    if (keys.count(key.substr(0, start) + "NAME" + key.substr(end))) return true;
    start = end + 1;
  }
  return false;
}

TEST(StudyKeys, EveryKeyOfTheShippedFilesIsListedForItsKind) {
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(source_path("studies"))) {
    if (e.path().extension() != ".toml") continue;
    const toml::table study = toml::parse_file(e.path().string());
    if (!study.contains("study")) continue;  // an optimization or budget file
    const std::string kind = study["study"]["kind"].value_or(std::string());
    const engine::KindKeys keys = engine::kind_keys(kind);
    const std::set<std::string> study_keys = listed(keys.study), model_keys = listed(keys.model);
    std::set<std::string> used;
    flatten(study, "", used);
    for (const auto& k : used) {
      if (k == "overrides") continue;
      EXPECT_TRUE(study_keys.count(k)) << e.path().filename() << ": key " << k << " is not in `poise keys " << kind << "`";
    }
    const fs::path model = e.path().parent_path() / study["study"]["model"].value_or(std::string());
    std::set<std::string> model_used;
    flatten(toml::parse_file(model.string()), "", model_used);
    for (const auto& k : model_used) {
      if (k == "declared") continue;
      // Tolerance tables are read per key; their keys are listed under each tolerance.
      EXPECT_TRUE(is_listed(k, model_keys)) << model.filename() << ": key " << k << " is not in `poise keys " << kind << "`";
    }
    ++files;
  }
  EXPECT_GE(files, 10u);
}

TEST(StudyKeys, TheCommandListsTheKindsAndTheirKeys) {
  test::TempDir d;
  auto r = test::run_poise(d, "keys");
  EXPECT_EQ(r.status, 0);
  for (const auto& name : engine::study_kind_names()) EXPECT_NE(r.out.find(name), std::string::npos) << name;
  r = test::run_poise(d, "keys gimbal_static_unbalance");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("[[group.load]]"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("[rotor]"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("[[reference]]"), std::string::npos) << r.out;
  // A key required with one setting only says so instead of "(required)".
  r = test::run_poise(d, "keys platform_balancing");
  EXPECT_EQ(r.status, 0) << r.err;
  for (const char* k : {"natural_frequency", "crossover"}) {
    const auto at = r.out.find(std::string("    ") + k + " ");
    ASSERT_NE(at, std::string::npos) << k << "\n" << r.out;
    const std::string line = r.out.substr(at, r.out.find('\n', at) - at);
    EXPECT_NE(line.find("required with loop = "), std::string::npos) << line;
    EXPECT_EQ(line.find("(required)"), std::string::npos) << line;
  }
  // A tolerance's two forms (tolerance with tolerance_is, or min and max) are alternatives:
  // none of the four keys is required alone.
  r = test::run_poise(d, "keys shaft_sag");
  EXPECT_EQ(r.status, 0) << r.err;
  const auto tol = r.out.find("[tolerances.span]");
  ASSERT_NE(tol, std::string::npos) << r.out;
  const std::string block = r.out.substr(tol, r.out.find("\n\n", tol) - tol);
  for (const char* k : {"tolerance ", "tolerance_is ", "min ", "max "}) {
    const auto at = block.find(std::string("    ") + k);
    ASSERT_NE(at, std::string::npos) << k << "\n" << block;
    const std::string line = block.substr(at, block.find('\n', at) - at);
    EXPECT_EQ(line.find("(required)"), std::string::npos) << line;
    EXPECT_NE(line.find("(optional)"), std::string::npos) << line;
  }
  EXPECT_NE(block.find("distribution"), std::string::npos);
  r = test::run_poise(d, "keys no_such_kind");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("seeker_los"), std::string::npos) << r.err;
  r = test::run_poise(d, "--help");
  for (const auto& name : engine::study_kind_names()) EXPECT_NE(r.out.find(name), std::string::npos) << name;
}

TEST(StudyKeys, AMisspelledKeyGetsTheNearestKnownOne) {
  test::TempDir d;
  std::string text = test::read_text(source_path("studies/gimbal_unbalance_mc.toml"));
  text = test::replace_once(text, "positions =", "postions =");
  text = test::replace_once(text, "model = \"../models/", "model = \"" + source_path("models") + "/");
  const std::string path = d.file("typo.toml");
  test::write_text(path, text);
  const auto r = test::run_poise(d, "validate '" + path + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("group[0].postions"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("did you mean 'positions'?"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace poise
