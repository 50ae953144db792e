#pragma once
// Shared pieces of the fuzz target's input kinds (fuzz_inputs.cc): the private temporary
// folder files are written to, reading and writing whole files, and the seed writer.
#include <filesystem>
#include <string>
#include <string_view>

namespace poise::fuzz {

namespace fs = std::filesystem;

inline const fs::path kSource = POISE_SOURCE_DIR;

/// The private temporary folder (laid out like the repository: studies/, models/).
const fs::path& work_dir();

void write_file(const fs::path& path, std::string_view text);
std::string read_file(const fs::path& path);

/// Adds one seed: the selector byte, then the text.
using AddSeed = void (*)(char selector, const std::string& text);

// Input kinds beyond the study and model files (selectors in fuzz_inputs.cc).
void seed_data_inputs(AddSeed add);   ///< torque CSV 'c', record 'r', OBJ 'o', STL 's'
void seed_plan_inputs(AddSeed add);   ///< optimization 'p', budget 'b'
void fuzz_torque_csv(std::string_view text);
void fuzz_record(std::string_view text);
void fuzz_mesh(std::string_view text, const char* extension);
void fuzz_optimization(std::string_view text);
void fuzz_budget(std::string_view text);

}  // namespace poise::fuzz
