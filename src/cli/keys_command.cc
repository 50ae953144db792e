#include "cli/keys_command.h"

#include <iostream>
#include <memory>
#include <sstream>

#include <nlohmann/json.hpp>

#include "engine/kind_interface/study_kind.h"
#include "engine/study_files/study_keys.h"

namespace poise::cli {

std::string study_kinds_text() {
  // Each kind's name, then its summary wrapped to 92 columns under it.
  std::string out;
  for (const auto* k : engine::study_kinds()) {
    out += "  " + k->name() + "\n";
    std::string line = "     ";
    std::istringstream words(k->summary() + ".");
    for (std::string w; words >> w;) {
      if (line.size() + 1 + w.size() > 92) {
        out += line + "\n";
        line = "     ";
      }
      line += " " + w;
    }
    out += line + "\n";
  }
  return out;
}

KeysHandler add_keys_command(CLI::App& app) {
  struct Options {
    std::string kind;
    bool json = false;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub = app.add_subcommand(
      "keys", "list every key of a study kind's study and model files (generated from the program's own reading)");
  sub->add_option("KIND", opt->kind, "a study kind (without it: the kinds)");
  sub->add_flag("--json", opt->json, "print the keys as JSON");
  sub->footer("Example: poise keys gimbal_static_unbalance");
  return [sub, opt]() -> std::optional<int> {
    if (!*sub) return std::nullopt;
    if (opt->kind.empty()) {
      std::cout << "Study kinds ([study] kind = ...):\n"
                << study_kinds_text() << "\n`poise keys KIND` lists the keys of a kind's study and model files.\n";
      return 0;
    }
    try {
      engine::study_kind(opt->kind);
    } catch (const std::exception& e) {
      std::cerr << "poise keys: " << e.what() << '\n';
      return 2;
    }
    const engine::KindKeys keys = engine::kind_keys(opt->kind);
    if (opt->json) {
      auto to_json = [](const std::vector<engine::KeyDoc>& v) {
        nlohmann::json a = nlohmann::json::array();
        for (const auto& k : v) {
          a.push_back({{"key", k.path}, {"expected", k.expected}, {"required", k.required}, {"default", k.fallback}});
        }
        return a;
      };
      std::cout
          << nlohmann::json{{"kind", opt->kind}, {"study", to_json(keys.study)}, {"model", to_json(keys.model)}}.dump(2)
          << '\n';
    } else {
      std::cout << engine::keys_text(opt->kind, keys);
    }
    return 0;
  };
}

}  // namespace poise::cli
