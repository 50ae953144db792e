// Input kinds of the fuzz target: optimization files ('p') and budget files ('b'). See
// fuzz_inputs.cc for the selectors and what counts as a finding.
#include <string>
#include <string_view>

#include "budget/budget_check.h"
#include "budget/budget_file.h"
#include "fuzz_common.h"
#include "optimize/optimization_spec.h"

namespace poise::fuzz {

void seed_plan_inputs(AddSeed add) {
  for (const auto& e : fs::directory_iterator(kSource / "studies")) {
    if (e.path().extension() != ".toml") continue;
    const std::string text = read_file(e.path());
    if (text.find("[optimization]") != std::string::npos) add('p', text);
    if (text.find("[budget]") != std::string::npos) add('b', text);
  }
  // The nesting that overflowed toml++'s stack (issue 20): every TOML reader must refuse it.
  for (const char* f : {"deeply_dotted_key.toml", "deeply_nested_header.toml", "deeply_nested_inline_tables.toml",
                        "deeply_nested_arrays.toml", "huge_quantity.toml", "nan_quantity.toml"}) {
    const fs::path p = kSource / "tests/data/malformed" / f;
    if (!fs::exists(p)) continue;
    const std::string text = read_file(p);
    add('p', text);
    add('b', text);
  }
  // Values at the edges of double inside otherwise valid files.
  const fs::path budget = kSource / "studies/wang2011_budget.toml";
  if (fs::exists(budget)) {
    std::string text = read_file(budget);
    const auto at = text.find("requirement = \"1 px\"");
    if (at != std::string::npos) {
      for (const char* v : {"1e308 px", "1e-320 px", "0 px", "-1 px"}) {
        add('b', std::string(text).replace(at, 20, std::string("requirement = \"") + v + "\""));
      }
    }
  }
}

void fuzz_optimization(std::string_view text) {
  const fs::path file = work_dir() / "studies" / "fuzz_optimization.toml";
  write_file(file, text);
  (void)optimize::load_optimization(file.string());
}

void fuzz_budget(std::string_view text) {
  const fs::path file = work_dir() / "studies" / "fuzz_budget.toml";
  write_file(file, text);
  const budget::BudgetSpec spec = budget::load_budget(file.string());
  (void)budget::check_budget(spec);
}

}  // namespace poise::fuzz
