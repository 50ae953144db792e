// Bad input (issue 9): `poise validate` on every file of tests/data/malformed/ (each study
// file wrong in one way; tests/data/malformed/models/ holds the broken model files some of
// them use). Every file must be refused with exit status 2 ("invalid input, nothing ran"),
// never a crash, a hang or exit 1, with a message on stderr that names the file (and the line
// where the error has one) and says what was expected.
//
// A file states what its message must contain in header comments:
//   # expect-where: <text>   e.g. "unknown_key.toml:12" (file and line); default: the file name
//   # expect-text: <text>    any number of these, e.g. "expected an integer from 1 to 1000000000"
//   # expect-exit: <n>       default 2
// Files that cannot carry a comment (empty, binary) get the default checks. New files in the
// folder are picked up by themselves; tests/data/malformed/README.md must list each one.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/error.h"
#include "engine/study_files/toml_nesting.h"
#include "engine/study_files/toml_reader.h"
#include "test_util.h"

namespace poise::test {
namespace {

namespace fs = std::filesystem;

fs::path corpus_dir() { return fs::path(::poise::test::source_dir()) / "tests" / "data" / "malformed"; }

std::vector<std::string> corpus_files() {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(corpus_dir())) {
    if (e.is_regular_file() && e.path().extension() != ".md") out.push_back(e.path().filename().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

struct Expectation {
  int exit = 2;
  std::vector<std::string> where, texts;
};

// Reads the "# expect-..." comments of the file's first lines (after a byte-order mark).
Expectation expectation_of(const std::string& text) {
  Expectation x;
  std::size_t pos = 0;
  while (text.compare(pos, 3, "\xef\xbb\xbf") == 0) pos += 3;
  while (pos < text.size() && text[pos] == '#') {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(pos, end - pos);
    auto value = [&](const std::string& tag) -> std::optional<std::string> {
      const std::string prefix = "# " + tag + ": ";
      if (line.rfind(prefix, 0) != 0) return std::nullopt;
      return line.substr(prefix.size());
    };
    if (auto v = value("expect-exit")) x.exit = std::atoi(v->c_str());
    if (auto v = value("expect-where")) x.where.push_back(*v);
    if (auto v = value("expect-text")) x.texts.push_back(*v);
    pos = end + 1;
  }
  return x;
}

// gtest parameter names: letters, digits and '_' only.
std::string param_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string s = info.param;
  for (char& c : s) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return s;
}

class MalformedCorpus : public ::testing::TestWithParam<std::string> {};

TEST_P(MalformedCorpus, RefusedWithAClearMessage) {
  const std::string name = GetParam();
  const std::string path = (corpus_dir() / name).string();
  const Expectation x = expectation_of(read_text(path));
  TempDir dir;
  const std::string out = dir.file("stdout.txt"), err = dir.file("stderr.txt");
  // `timeout` turns a hang into status 124 and passes a signal on as 128 + signal.
  const std::string cmd = "timeout 120 '" + ::poise::test::poise_binary() + "' validate '" + path + "' >'" + out +
                          "' 2>'" + err + "'";
  const int raw = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(raw)) << name << ": poise did not exit normally";
  const int status = WEXITSTATUS(raw);
  const std::string so = read_text(out), se_full = read_text(err);
  // Failure output shows at most 4000 characters of stderr (a message must not be huge anyway).
  const std::string se = se_full.size() > 4000 ? se_full.substr(0, 4000) + "..." : se_full;
  EXPECT_LE(se_full.size(), 20000u) << name << ": a message of " << se_full.size() << " bytes";
  ASSERT_NE(status, 124) << name << ": poise validate hung (killed after 120 s)";
  ASSERT_LT(status, 128) << name << ": poise validate was killed by signal " << status - 128 << "\n" << se;
  EXPECT_EQ(status, x.exit) << name << ": stderr:\n" << se;
  if (status == 2) {
    EXPECT_NE(se_full.find("Nothing was run."), std::string::npos) << name << ":\n" << se;
  }
  EXPECT_EQ(so.find("valid."), std::string::npos) << name << ": validated:\n" << so;
  EXPECT_NE(se_full.find("expected"), std::string::npos) << name << ": does not say what was expected:\n" << se;
  if (x.where.empty()) {
    EXPECT_NE(se_full.find(name), std::string::npos) << name << ": the message does not name the file:\n" << se;
  }
  for (const auto& w : x.where) {
    EXPECT_NE(se_full.find(w), std::string::npos) << name << ": the message lacks \"" << w << "\":\n" << se;
  }
  for (const auto& t : x.texts) {
    EXPECT_NE(se_full.find(t), std::string::npos) << name << ": the message lacks \"" << t << "\":\n" << se;
  }
}

// The prefix "malformed" lets `ctest -R malformed` select these tests.
INSTANTIATE_TEST_SUITE_P(malformed, MalformedCorpus, ::testing::ValuesIn(corpus_files()), param_name);

class MalformedFolder : public ::testing::TestWithParam<std::string> {};

TEST_P(MalformedFolder, ReadmeListsEveryFile) {
  const std::string readme = read_text((corpus_dir() / GetParam()).string());
  ASSERT_FALSE(readme.empty());
  std::vector<std::string> files = corpus_files();
  for (const auto& e : fs::directory_iterator(corpus_dir() / "models")) files.push_back(e.path().filename().string());
  EXPECT_GE(files.size(), 25u);
  for (const auto& f : files) EXPECT_NE(readme.find("`" + f + "`"), std::string::npos) << f << " is not in README.md";
}

INSTANTIATE_TEST_SUITE_P(malformed, MalformedFolder, ::testing::Values(std::string("README.md")), param_name);

// The nesting limit, measured before toml++ parses (it would overflow its stack on 50,000
// levels): header, dotted key, arrays and inline tables count together; strings, comments
// and numbers do not.
TEST(TomlNesting, CountsTablesKeysArraysAndInlineTablesTogether) {
  using engine::find_too_deep_nesting;
  auto dots = [](int levels) {
    std::string k = "a";
    for (int i = 1; i < levels; ++i) k += ".a";
    return k;
  };
  EXPECT_FALSE(find_too_deep_nesting(dots(64) + " = 1\n"));
  const auto key = find_too_deep_nesting("x = 1\n" + dots(65) + " = 1\n");
  ASSERT_TRUE(key);
  EXPECT_EQ(key->line, 2);
  EXPECT_FALSE(find_too_deep_nesting("[" + dots(64) + "]\n"));
  EXPECT_TRUE(find_too_deep_nesting("[[" + dots(65) + "]]\n"));
  // A header of 40 and a dotted key of 30 below it: 70 levels.
  const auto both = find_too_deep_nesting("[" + dots(40) + "]\n" + dots(30) + " = 1\n");
  ASSERT_TRUE(both);
  EXPECT_EQ(both->line, 2);
  EXPECT_FALSE(find_too_deep_nesting("[" + dots(40) + "]\n" + dots(24) + " = 1\n"));
  // The key x and 63 arrays: 64 levels; one more array is too deep.
  EXPECT_FALSE(find_too_deep_nesting("x = " + std::string(63, '[') + std::string(63, ']') + "\n"));
  EXPECT_TRUE(find_too_deep_nesting("x = " + std::string(64, '[') + std::string(64, ']') + "\n"));
  // Arrays spanning lines keep their depth.
  EXPECT_TRUE(find_too_deep_nesting("x = " + std::string(40, '[') + "\n" + std::string(30, '[') + "\n"));
  // Dots and brackets in strings, comments and numbers are not nesting.
  const std::string many(500, '.');
  EXPECT_FALSE(find_too_deep_nesting("s = \"" + many + std::string(100, '[') + "\"\n"));
  EXPECT_FALSE(find_too_deep_nesting("s = '''\n" + many + "\n'''\n# " + many + std::string(100, '{') + "\nv = 1.5\n"));
  EXPECT_FALSE(find_too_deep_nesting("\"" + many + "\" = 1\n"));  // a quoted key with dots: one level
  EXPECT_FALSE(find_too_deep_nesting("[study]\nkind = \"gimbal\" # [[[[\n[[group]]\nload = [{ mass = \"1 kg\" }]\n"));
}

TEST(TomlNesting, RealFilesAreWellWithinTheLimit) {
  for (const char* f : {"studies/los_seeker_wang2011.toml", "studies/gimbal_unbalance_mc.toml",
                        "studies/platform_balancing_sequence.toml", "models/seeker_two_axis_wang2011.toml",
                        "models/platform_three_gimbal.toml"}) {
    EXPECT_FALSE(engine::find_too_deep_nesting(read_text(source_path(f)))) << f;
  }
}

TEST(TomlFile, ReadAgainAfterAChangeGivesTheNewTable) {
  // Files are parsed once per text (a model is read by several stages): a changed file must
  // still be read anew.
  TempDir d;
  const std::string f = d.file("m.toml");
  write_text(f, "x = 1\n");
  EXPECT_EQ(engine::parse_toml_file(f)["x"].value<int>(), 1);
  EXPECT_EQ(engine::parse_toml_file(f)["x"].value<int>(), 1);
  write_text(f, "x = 2\n");
  EXPECT_EQ(engine::parse_toml_file(f)["x"].value<int>(), 2);
  write_text(f, "x = [[[\n");
  EXPECT_THROW(engine::parse_toml_file(f), engine::ValidationError);
}

TEST(ErrorList, AtMostTwentyErrorsThenHowManyMore) {
  std::vector<InputError> errors;
  for (int k = 1; k <= 27; ++k) errors.emplace_back(SourceLocation{"s.toml", k, 1}, "key" + std::to_string(k), "1", "x");
  const std::string what = engine::ValidationError(errors).what();
  EXPECT_NE(what.find("27 errors in the input"), std::string::npos) << what;
  EXPECT_NE(what.find("key20"), std::string::npos);
  EXPECT_EQ(what.find("key21"), std::string::npos) << what;
  EXPECT_NE(what.find("\n  and 7 more"), std::string::npos) << what;
  errors.erase(errors.begin() + 20, errors.end());
  EXPECT_EQ(std::string(engine::ValidationError(errors).what()).find("more"), std::string::npos);
  // A key or value of a million characters is echoed by its start and its length.
  const InputError huge(SourceLocation{"s.toml", 3, 1}, std::string(1000000, 'k'), std::string(1000000, 'v'), "x");
  const std::string h = huge.what();
  EXPECT_LT(h.size(), 400u) << h.substr(0, 400);
  EXPECT_NE(h.find("... (1000000 bytes)"), std::string::npos);
}

}  // namespace
}  // namespace poise::test
