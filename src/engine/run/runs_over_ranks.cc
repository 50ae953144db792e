#include "engine/run/runs_over_ranks.h"

#include <cstdint>
#include <exception>
#include <string>

#include "core/error.h"
#include "sampling/distributed.h"

namespace poise::engine {

using nlohmann::json;

std::vector<json> runs_over_ranks(std::size_t count, const std::function<json(std::size_t)>& run) {
  const auto ranks = static_cast<std::size_t>(sampling::Cluster::size());
  const auto me = static_cast<std::size_t>(sampling::Cluster::rank());
  std::vector<json> results;
  if (ranks == 1) {
    results.reserve(count);
    for (std::size_t i = 0; i < count; ++i) results.push_back(run(i));
    return results;
  }
  // This rank's runs, each result or the message of what stopped it. CBOR carries every
  // number bit for bit (NaN too) to rank 0. Run i is rank (i + 1) mod ranks's: rank 0, which
  // also finishes the run's statistics and writes its folder, gets the fewer when they do not
  // divide evenly.
  json mine = json::array();
  for (std::size_t i = (me + ranks - 1) % ranks; i < count; i += ranks) {
    try {
      mine.push_back({{"result", run(i)}});
    } catch (const std::exception& e) {
      mine.push_back({{"error", e.what()}});
    }
  }
  const std::vector<std::uint8_t> bytes = json::to_cbor(mine);
  const std::vector<std::string> all = sampling::Cluster::gather(std::string(bytes.begin(), bytes.end()));
  if (!sampling::Cluster::root()) return results;
  results.resize(count);
  for (std::size_t q = 0; q < all.size(); ++q) {
    const json theirs = json::from_cbor(all[q]);
    for (std::size_t k = 0; k < theirs.size(); ++k) {
      const std::size_t i = (q + ranks - 1) % ranks + k * ranks;
      POISE_INVARIANT(i < count, "a rank sent more runs than it was given");
      if (theirs[k].contains("error")) {
        throw Error("run " + std::to_string(i + 1) + " of " + std::to_string(count) + " (on MPI rank " +
                    std::to_string(q) + "): " + theirs[k]["error"].get<std::string>());
      }
      results[i] = theirs[k]["result"];
    }
  }
  return results;
}

}  // namespace poise::engine
