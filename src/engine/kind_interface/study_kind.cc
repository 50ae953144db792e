#include "engine/kind_interface/study_kind.h"

#include <mutex>

#include "core/error.h"

namespace poise::engine {
namespace {

std::vector<std::unique_ptr<StudyKind>>& table() {
  static std::vector<std::unique_ptr<StudyKind>> kinds;
  return kinds;
}

}  // namespace

std::map<std::string, std::string> StudyKind::apply_study_overrides(
    StudyConfig& /*cfg*/, const std::map<std::string, std::string>& overrides) const {
  return overrides;
}

McResult StudyKind::evaluate(const StudyConfig& cfg, const std::map<std::string, std::string>&, std::size_t,
                             std::uint64_t, int) const {
  throw Error(cfg.file + ": a " + name() +
              " study cannot be the base of an optimization (its kind has no in-memory "
              "evaluation); optimize over a study of a kind that streams its samples (`poise --help` lists the kinds)");
}

std::unique_ptr<InputEvaluator> StudyKind::input_evaluator(const StudyConfig& cfg,
                                                           const std::map<std::string, std::string>&,
                                                           std::uint64_t) const {
  throw Error(cfg.file + ": a " + name() +
              " study cannot be evaluated at inputs you give: its samples.csv inputs "
              "do not determine a sample (some are derived from others, or drawn per test); run it instead "
              "(poise run, poise.run), whose outputs come with the inputs each sample drew");
}

StudyConfig StudyKind::model_study(const std::string& model_path) const {
  throw Error(model_path + ": a " + name() + " study has no Monte Carlo on a model file alone");
}

void register_study_kind(std::unique_ptr<StudyKind> kind) {
  for (const auto& k : table()) {
    if (k->name() == kind->name()) throw Error("study kind '" + kind->name() + "' registered twice");
  }
  table().push_back(std::move(kind));
}

const StudyKind& study_kind(const std::string& name) {
  for (const auto& k : table()) {
    if (k->name() == name) return *k;
  }
  std::string all;
  for (const auto& k : table()) all += (all.empty() ? "" : ", ") + k->name();
  throw Error("no study kind '" + name + "'; the kinds are: " + all);
}

std::vector<const StudyKind*> study_kinds() {
  std::vector<const StudyKind*> out;
  for (const auto& k : table()) out.push_back(k.get());
  return out;
}

std::vector<std::string> study_kind_names() {
  std::vector<std::string> out;
  for (const auto& k : table()) out.push_back(k->name());
  return out;
}

}  // namespace poise::engine
