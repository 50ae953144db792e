#include "engine/hdf5_handles.h"

namespace poise::studies::hdf5 {

void quiet() {
  static const bool once = [] {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
  }();
  (void)once;
}

std::string system_reason() {
  std::string reason;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, [](unsigned, const H5E_error2_t* e, void* data) -> herr_t {
    auto& out = *static_cast<std::string*>(data);
    if (!out.empty() || e == nullptr || e->desc == nullptr) return 0;
    const std::string desc = e->desc;
    const std::string key = "error message = '";
    if (const auto at = desc.find(key); at != std::string::npos) {
      const auto end = desc.find('\'', at + key.size());
      out = desc.substr(at + key.size(), end == std::string::npos ? std::string::npos : end - at - key.size());
    }
    return 0;
  }, &reason);
  return reason;
}

std::string failed(const std::string& what) {
  const std::string reason = system_reason();
  return reason.empty() ? what : what + ": " + reason;
}

hid_t unlocked_access() {
  static const hid_t fapl = [] {
    const hid_t p = H5Pcreate(H5P_FILE_ACCESS);
    H5Pset_file_locking(p, false, true);
    return p;
  }();
  return fapl;
}

}  // namespace poise::studies::hdf5
