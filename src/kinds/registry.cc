#include "kinds/registry.h"

#include <mutex>

#include "engine/study_kind.h"
#include "kinds/balancing_machine/balancing_kind.h"
#include "kinds/geometry_mass_properties/geometry_mass_kind.h"
#include "kinds/gimbal_static_unbalance/gimbal_kind.h"
#include "kinds/los_obstruction/obstruction_kind.h"
#include "kinds/platform_balancing/platform_kind.h"
#include "kinds/seeker_los/seeker_los_kind.h"

namespace poise::studies {

void register_study_kinds() {
  static std::once_flag once;
  std::call_once(once, [] {
    register_study_kind(make_seeker_los_kind());
    register_study_kind(make_gimbal_static_unbalance_kind());
    register_study_kind(make_balancing_machine_kind());
    register_study_kind(make_platform_balancing_kind());
    register_study_kind(make_geometry_mass_properties_kind());
    register_study_kind(make_los_obstruction_kind());
  });
}

}  // namespace poise::studies
