#include "engine/results/hdf5_handles.h"

#include "core/error.h"

namespace poise::engine::hdf5 {

void quiet() {
  static const bool once = [] {
    // No cleanup of HDF5's own at exit: every file Poise opens is closed by its handles, and
    // after a failed write (a full disk) a file whose close failed stays in the library's
    // table, which H5_term_library then closed again and crashed in (SIGSEGV after the
    // run's error was printed). Called before any other HDF5 function, as it must be.
    H5dont_atexit();
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
  }();
  (void)once;
}

std::string system_reason() {
  std::string reason;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_DOWNWARD,
      [](unsigned, const H5E_error2_t* e, void* data) -> herr_t {
        auto& out = *static_cast<std::string*>(data);
        if (!out.empty() || e == nullptr || e->desc == nullptr) return 0;
        const std::string desc = e->desc;
        const std::string key = "error message = '";
        if (const auto at = desc.find(key); at != std::string::npos) {
          const auto end = desc.find('\'', at + key.size());
          out = desc.substr(at + key.size(), end == std::string::npos ? std::string::npos : end - at - key.size());
        }
        return 0;
      },
      &reason);
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

void text_attribute(hid_t obj, const std::string& name, const std::string& value) {
  Id type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.get(), H5T_VARIABLE);
  H5Tset_cset(type.get(), H5T_CSET_UTF8);
  Id space(H5Screate(H5S_SCALAR), H5Sclose);
  Id attr(H5Acreate2(obj, name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  const char* p = value.c_str();
  if (!attr.ok() || H5Awrite(attr.get(), type.get(), &p) < 0) throw Error(failed("cannot write attribute " + name));
}

void number_attribute(hid_t obj, const std::string& name, std::uint64_t value) {
  Id space(H5Screate(H5S_SCALAR), H5Sclose);
  Id attr(H5Acreate2(obj, name.c_str(), H5T_STD_U64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!attr.ok() || H5Awrite(attr.get(), H5T_NATIVE_UINT64, &value) < 0) {
    throw Error(failed("cannot write attribute " + name));
  }
}

}  // namespace poise::engine::hdf5
