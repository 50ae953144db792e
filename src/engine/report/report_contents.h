#pragma once
/// A report page's table of contents: every section heading (<h2>) gets an id (its own, or
/// one made from its words, unique in the page) and a linked list of them is set before the
/// first section, after the answer. Every report page of the engine ends with it.
#include <string>

namespace poise::engine {

/// The page with its section ids and contents list (unchanged with fewer than three sections).
std::string with_contents(const std::string& page);

}  // namespace poise::engine
