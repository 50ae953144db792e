// Writes the meshes of the worked example of a designer's own parts (README, "Designer: mass
// properties of your CAD parts") into a folder, as a CAD system would export them: lengths in
// mm, each part in its own frame, in the formats designers meet (binary STL, ASCII STL, OBJ).
//
//   rotor/  the gimbal rotor of examples/user_parts/rotor_parts.toml (z the gimbal axis):
//     rotor_disk.stl     aluminium disk 130 mm x 12 mm with a 16 mm bore (binary STL)
//     hub.obj            steel hub 40 mm x 18 mm on the shaft, above the disk (OBJ)
//     shaft.stl          steel shaft 16 mm x 80 mm (ASCII STL)
//     clump_weight.stl   steel clump weight 16 mm x 8 mm, modelled at its own origin and placed
//                        by the parts file on the 51 mm hole circle (binary STL)
//   seeker/ the two-axis seeker's frames and housing (geometry/generators.h, Wang 2011
//     dimensions): ring.stl (yaw frame), barrel.stl and pitch_shafts.stl (pitch frame),
//     housing.stl, posts.stl, window.stl, each in its frame's coordinates (binary STL).
//
// Usage: poise_make_example_meshes OUT_DIR      (scripts/make_example_meshes.sh)
#include <filesystem>
#include <iostream>

#include "geometry/generators.h"
#include "geometry/mesh_check.h"
#include "geometry/mesh_io.h"

namespace {

using namespace poise::geometry;
constexpr double kMm = 1e-3;

// Every file written, read back as `poise mass-properties` reads it (float32 STL, vertices
// welded), passes its check.
void check_file(const std::string& path) {
  const Mesh m = load_mesh(path, kMm);
  require_valid_mesh(m);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: poise_make_example_meshes OUT_DIR\n";
    return 2;
  }
  try {
    const std::filesystem::path out = argv[1];
    std::filesystem::create_directories(out / "rotor");
    std::filesystem::create_directories(out / "seeker");
    const int n = 128;
    const Mesh disk = tube(8 * kMm, 65 * kMm, 0.0, 12 * kMm, n, "rotor_disk");
    const Mesh hub = tube(8 * kMm, 20 * kMm, 12 * kMm, 30 * kMm, n, "hub");
    const Mesh shaft = cylinder(8 * kMm, -20 * kMm, 60 * kMm, n, "shaft");
    const Mesh clump = cylinder(8 * kMm, 0.0, 8 * kMm, 48, "clump_weight");
    write_stl(disk, (out / "rotor" / "rotor_disk.stl").string(), kMm);
    write_obj(hub, (out / "rotor" / "hub.obj").string(), kMm);
    write_ascii_stl(shaft, (out / "rotor" / "shaft.stl").string(), kMm);
    write_stl(clump, (out / "rotor" / "clump_weight.stl").string(), kMm);
    for (const char* f : {"rotor_disk.stl", "hub.obj", "shaft.stl", "clump_weight.stl"}) {
      check_file((out / "rotor" / f).string());
    }

    const SeekerMeshes s = seeker_meshes(SeekerGeometry{});
    const std::pair<const char*, const Mesh*> seeker[] = {
        {"ring", &s.ring},       {"barrel", &s.barrel}, {"pitch_shafts", &s.pitch_shafts},
        {"housing", &s.housing}, {"posts", &s.posts},   {"window", &s.window}};
    for (const auto& [name, mesh] : seeker) {
      const std::string path = (out / "seeker" / (std::string(name) + ".stl")).string();
      write_stl(*mesh, path, kMm);
      check_file(path);
    }
    std::cout << "wrote the example meshes (mm) to " << out.string() << "/rotor and " << out.string() << "/seeker\n";
  } catch (const std::exception& e) {
    std::cerr << "poise_make_example_meshes: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
