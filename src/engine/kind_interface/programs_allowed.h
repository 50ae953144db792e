#pragma once
/// Whether this process may start the programs model files name (kind = "external"). Off by
/// default: a study received from someone else must not run code when it is opened, validated
/// or read; `poise run --allow-programs` (Python: allow_programs=True) turns it on for a run.
namespace poise::engine {

bool programs_allowed();
void allow_programs(bool allowed);

}  // namespace poise::engine
