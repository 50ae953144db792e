#include "engine/run/runs_over_ranks.h"

#include <algorithm>
#include <cstdint>
#include <exception>
#include <string>

#include "core/error.h"
#include "sampling/distributed.h"

namespace poise::engine {

using nlohmann::json;

std::vector<json> runs_over_ranks(std::size_t count, const std::function<json(std::size_t)>& run) {
  const auto ranks = static_cast<std::size_t>(sampling::Cluster::size());
  std::vector<json> results;
  if (ranks == 1) {
    results.reserve(count);
    for (std::size_t i = 0; i < count; ++i) results.push_back(run(i));
    return results;
  }
  // This rank's runs, each with its result or the message of what stopped it, taken one at a
  // time from the runs no rank has taken yet: a rank that starts late (rank 0 finishes the
  // run's statistics first) or whose runs are slower takes fewer. CBOR carries every number
  // bit for bit (NaN too) to rank 0.
  json mine = json::array();
  sampling::SharedCounter runs;
  for (std::size_t i = runs.next(); i < count; i = runs.next()) {
    try {
      mine.push_back({{"run", i}, {"result", run(i)}});
    } catch (const std::exception& e) {
      mine.push_back({{"run", i}, {"error", e.what()}});
    }
  }
  const std::vector<std::uint8_t> bytes = json::to_cbor(mine);
  const std::vector<std::string> all = sampling::Cluster::gather(std::string(bytes.begin(), bytes.end()));
  if (!sampling::Cluster::root()) return results;
  results.resize(count);
  std::vector<bool> made(count, false);
  std::size_t first_error = count;
  std::string error;
  for (std::size_t q = 0; q < all.size(); ++q) {
    for (const json& r : json::from_cbor(all[q])) {
      const auto i = r["run"].get<std::size_t>();
      POISE_INVARIANT(i < count && !made[i], "every run is made once");
      made[i] = true;
      if (!r.contains("error")) {
        results[i] = r["result"];
      } else if (i < first_error) {  // the first run's error, whichever rank reached it first
        first_error = i;
        error = "run " + std::to_string(i + 1) + " of " + std::to_string(count) + " (on MPI rank " + std::to_string(q) +
                "): " + r["error"].get<std::string>();
      }
    }
  }
  if (first_error < count) throw Error(error);
  POISE_INVARIANT(std::all_of(made.begin(), made.end(), [](bool m) { return m; }), "every run is made");
  return results;
}

}  // namespace poise::engine
