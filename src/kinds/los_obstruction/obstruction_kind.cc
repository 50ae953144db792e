#include "kinds/los_obstruction/obstruction_kind.h"

#include "engine/kind_interface/procedure_kind.h"
#include "kinds/los_obstruction/obstruction_sections.h"
#include "kinds/los_obstruction/obstruction_study.h"

namespace poise::kinds::los_obstruction {
using namespace poise::engine;
namespace {

class LosObstructionKind final : public ProcedureKind {
 public:
  std::string name() const override { return "los_obstruction"; }
  std::string summary() const override {
    return "the optical beam of a two-axis seeker traced through its frames and housing over the field of regard "
           "(unobstructed share) and the clearance of the moving frames, nominal and over the shafting tolerances "
           "(model: a seeker model with [geometry])";
  }
  std::unique_ptr<KindSections> read_sections(TomlReader& root, const StudyConfig&) const override {
    return read_obstruction_sections(root);
  }
  std::string validate(const StudyConfig& cfg) const override { return validate_obstruction_study(cfg); }
  std::unique_ptr<ProcedureStudy> make_study(const StudyConfig& cfg, const std::map<std::string, std::string>& o,
                                             std::size_t samples, std::uint64_t seed) const override {
    return make_obstruction_study(cfg, o, samples, seed);
  }
};

}  // namespace

std::unique_ptr<StudyKind> make_los_obstruction_kind() { return std::make_unique<LosObstructionKind>(); }

}  // namespace poise::kinds::los_obstruction
