#pragma once
/// Reading and writing meshes: Wavefront OBJ and STL (binary and ASCII).
///
/// OBJ: `v x y z [w]` (or `v x y z r g b`) vertices, `f i j k ...` faces (polygons are
/// triangulated by ear clipping, geometry/polygon_triangulation.h; `i`, `i/t`, `i//n`, `i/t/n` and negative, relative
/// indices accepted); `vt`, `vn`, `vp`, `o`, `g`, `s`, `usemtl`, `mtllib`, `l`, `p` and comments are skipped; any other
/// statement is an error. STL: binary when the size is exactly 84 + 50 n bytes for the n the header declares, else
/// ASCII (`solid` ... `facet normal` / `outer loop` / 3 x `vertex` / `endloop` / `endfacet` ... `endsolid`, possibly
/// several solids one after another: one mesh). STL repeats vertices per triangle; equal coordinates are merged so the
/// mesh is indexed (and check_closed() can judge it). STL normals are ignored: orientation comes from the vertex order,
/// as the format specifies.
///
/// Lengths in the file are in `unit_m` metres per file unit (CAD exports are usually mm:
/// pass 1e-3). A malformed file throws MeshFormatError, whose message names the file, the
/// line (text formats) or triangle index (binary STL) and what is wrong.
#include <istream>
#include <string>

#include "core/error.h"
#include "geometry/mesh.h"
#include "geometry/mesh_needles.h"
#include "geometry/mesh_weld.h"

namespace poise::geometry {

class MeshFormatError : public Error {
 public:
  using Error::Error;
};

/// What load_mesh() repaired: vertices welded, zero-area triangles the surface does not need.
struct LoadReport {
  WeldReport weld;
  NeedleReport needles;
};

/// By extension (.obj, .stl, case-insensitive); the same for both: vertices closer than the
/// weld tolerance are welded (geometry/mesh_weld.h), `weld_m` in metres (< 0: the default,
/// relative to the part's size; 0: none), then the zero-area triangles the surface does not
/// need are dropped (geometry/mesh_needles.h); what was done goes to `report` if given. The
/// mesh remembers `unit_m` (Mesh::unit_m), so messages give coordinates in the file's unit.
Mesh load_mesh(const std::string& path, double unit_m = 1.0, LoadReport* report = nullptr, double weld_m = -1.0);
Mesh read_obj(std::istream& in, const std::string& name, double unit_m = 1.0);
/// `bytes`: the whole file.
Mesh read_stl(const std::string& bytes, const std::string& name, double unit_m = 1.0);

/// The text of an OBJ file (vertices in `unit_m` per file unit).
std::string obj_text(const Mesh& mesh, double unit_m = 1.0);
/// The bytes of a binary STL file.
std::string stl_bytes(const Mesh& mesh, double unit_m = 1.0);
/// The text of an ASCII STL file (17 significant digits, so it reads back to the same doubles).
std::string ascii_stl_text(const Mesh& mesh, double unit_m = 1.0);

/// Writes OBJ (vertices in `unit_m` per file unit). Throws poise::Error naming the file and
/// the system's reason if it cannot be written.
void write_obj(const Mesh& mesh, const std::string& path, double unit_m = 1.0);
/// Writes binary STL.
void write_stl(const Mesh& mesh, const std::string& path, double unit_m = 1.0);
/// Writes ASCII STL (17 significant digits, so it reads back to the same doubles).
void write_ascii_stl(const Mesh& mesh, const std::string& path, double unit_m = 1.0);

}  // namespace poise::geometry
