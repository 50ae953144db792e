#pragma once
/// Reading a campaign's [design] (balancing/campaign.h documents its keys): the machine's design
/// study, the real figures compared with its outputs, and an optional model key to calibrate.
#include <string>

#include "balancing/campaign.h"
#include "engine/study_files/toml_reader.h"

namespace poise::balancing {

/// [design] of `c` (its sensors and planes already read); relative paths from the campaign's folder.
DesignLink read_design_link(engine::TomlReader& design, const BalancingCampaign& c, const std::string& campaign_path);

}  // namespace poise::balancing
