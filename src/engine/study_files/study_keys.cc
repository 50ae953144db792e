#include "engine/study_files/study_keys.h"

#include <sstream>

#include "engine/kind_interface/study_kind.h"

namespace poise::engine {
namespace {

void print(std::ostringstream& out, const std::vector<KeyDoc>& keys) {
  std::string table = "\x01";
  for (const auto& k : keys) {
    if (k.expected.rfind("a table [", 0) == 0 || k.expected.rfind("tables [[", 0) == 0) continue;
    const auto dot = k.path.rfind('.');
    const std::string parent = dot == std::string::npos ? "" : k.path.substr(0, dot);
    const std::string name = dot == std::string::npos ? k.path : k.path.substr(dot + 1);
    if (parent != table) {
      table = parent;
      std::string header = parent;
      bool array = false;
      if (header.size() > 2 && header.compare(header.size() - 2, 2, "[]") == 0) {
        header.resize(header.size() - 2);
        array = true;
      }
      for (std::size_t p; (p = header.find("[]")) != std::string::npos;) header.erase(p, 2);
      out << "\n  " << (parent.empty() ? "(top level)" : array ? "[[" + header + "]]" : "[" + header + "]") << '\n';
    }
    out << "    " << name << std::string(name.size() < 24 ? 24 - name.size() : 1, ' ') << k.expected;
    if (k.required) {
      out << "  (required)";
    } else if (!k.fallback.empty() && k.fallback != "(optional)") {
      out << "  (default " << k.fallback << ")";
    } else {
      out << "  (optional)";
    }
    out << '\n';
  }
}

}  // namespace

KindKeys kind_keys(const std::string& kind) {
  const StudyKind& k = study_kind(kind);
  KeySchemaRecorder recorder(kind);
  try {
    StudyConfig cfg = load_study(kSchemaStudyFile);
    k.validate(cfg);
  } catch (const std::exception&) {
    // The stand-in values of an empty file may stop a kind's validation after its readers ran.
  }
  return {recorder.study_keys, recorder.model_keys};
}

std::string keys_text(const std::string& kind, const KindKeys& keys) {
  std::ostringstream out;
  out << "Keys of a " << kind << " study file (generated from the program's own reading of the files):\n";
  print(out, keys.study);
  out << "\nKeys of its model file:\n";
  print(out, keys.model);
  out << "\nEvery quantity carries its unit (\"0.004 mm\", \"30 deg\"). A tolerance table takes tolerance, "
         "distribution, tolerance_is and source (or min and max). [[reference]] tables may appear in the study "
         "and the model file.\n";
  return out.str();
}

}  // namespace poise::engine
