#include "geometry/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string_view>
#include <vector>

#include "core/format.h"
#include "geometry/mesh_needles.h"
#include "geometry/polygon_triangulation.h"
#include "geometry/vertex_welder.h"

namespace poise::geometry {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

[[noreturn]] void fail_line(const std::string& name, std::size_t line, const std::string& what) {
  throw MeshFormatError(name + ":" + std::to_string(line) + ": " + what);
}

bool parse_double(const std::string& tok, double& out) {
  const char* begin = tok.data();
  const char* end = tok.data() + tok.size();
  // from_chars takes no '+'; exporters write "+1.5e+01" (one '+', then a digit or a point).
  if (tok.size() > 1 && tok[0] == '+' && tok[1] != '-' && tok[1] != '+') ++begin;
  auto [p, ec] = std::from_chars(begin, end, out);
  return ec == std::errc() && p == end;
}

// A UTF-8 byte-order mark some exporters put before the text.
constexpr std::string_view kByteOrderMark = "\xEF\xBB\xBF";

// Whether `text` holds `word` in any letter case (ASCII).
bool contains_word_any_case(std::string_view text, std::string_view word) {
  return std::search(text.begin(), text.end(), word.begin(), word.end(), [](char a, char b) {
           return std::tolower(static_cast<unsigned char>(a)) == std::tolower(static_cast<unsigned char>(b));
         }) != text.end();
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream ss(line);
  std::string tok;
  while (ss >> tok) out.push_back(tok);
  return out;
}

// ASCII STL, read line by line: where the reader is in the grammar, and the facet being read.
class StlAsciiReader {
 public:
  StlAsciiReader(Mesh& mesh, const std::string& name, double unit_m)
      : mesh_(mesh), name_(name), unit_m_(unit_m), weld_(mesh) {}

  void read_line(const std::string& line, std::size_t ln) {
    const auto tok = split(line);
    if (tok.empty()) return;
    const std::string kw = lower(tok[0]);
    auto expect = [&](const std::string& what) {
      fail_line(name_, ln, "expected " + what + ", got '" + line.substr(0, 60) + "'");
    };
    switch (state_) {
      case State::kStart:
        if (kw != "solid") expect("'solid <name>' (ASCII STL)");
        state_ = State::kSolid;
        break;
      case State::kSolid:
        if (kw == "endsolid") {
          state_ = State::kEnd;
        } else if (kw == "facet") {
          if (tok.size() != 5 || lower(tok[1]) != "normal") expect("'facet normal nx ny nz'");
          for (int k = 2; k < 5; ++k) {
            double v;
            if (!parse_double(tok[k], v))
              fail_line(name_, ln, "facet normal component '" + tok[k] + "' is not a number");
          }
          facet_line_ = ln;
          state_ = State::kFacet;
        } else {
          expect("'facet normal nx ny nz' or 'endsolid'");
        }
        break;
      case State::kFacet:
        if (kw != "outer" || tok.size() != 2 || lower(tok[1]) != "loop") expect("'outer loop'");
        loop_.clear();
        state_ = State::kLoop;
        break;
      case State::kLoop:
        if (kw == "endloop") {
          end_loop(ln);
        } else if (kw == "vertex") {
          vertex(tok, ln);
        } else {
          expect("'vertex x y z' or 'endloop'");
        }
        break;
      case State::kEndLoop:
        if (kw != "endfacet") expect("'endfacet'");
        state_ = State::kSolid;
        break;
      case State::kEnd:
        // CAD systems write an assembly as several solids in one file: one part, one mesh.
        if (kw != "solid") expect("'solid <name>' or the end of the file after 'endsolid'");
        state_ = State::kSolid;
        break;
    }
  }

  // The file ended at line ln: after an 'endsolid', and with triangles.
  void finish(std::size_t ln) const {
    if (state_ != State::kEnd) {
      throw MeshFormatError(name_ + ":" + std::to_string(ln) + ": file ends inside a " +
                            (state_ == State::kSolid || state_ == State::kStart ? "solid (no 'endsolid')" : "facet"));
    }
    if (mesh_.triangles.empty()) throw MeshFormatError(name_ + ": no triangles");
  }

 private:
  enum class State { kStart, kSolid, kFacet, kLoop, kEndLoop, kEnd };

  // 'vertex x y z' in a loop: welded, in the mesh's unit.
  void vertex(const std::vector<std::string>& tok, std::size_t ln) {
    if (tok.size() != 4) fail_line(name_, ln, "vertex needs 3 coordinates, got " + std::to_string(tok.size() - 1));
    Eigen::Vector3d v;
    for (int k = 0; k < 3; ++k) {
      if (!parse_double(tok[k + 1], v[k]) || !std::isfinite(v[k])) {
        fail_line(name_, ln, "vertex coordinate '" + tok[k + 1] + "' is not a finite number");
      }
    }
    if (loop_.size() == 3) fail_line(name_, ln, "facet has more than 3 vertices; STL facets are triangles");
    loop_.push_back(weld_.add(v * unit_m_));
  }

  // 'endloop': the facet's triangle, with the line of its 'facet'.
  void end_loop(std::size_t ln) {
    if (loop_.size() != 3) {
      fail_line(name_, ln, "facet has " + std::to_string(loop_.size()) + " vertices; STL facets are triangles (3)");
    }
    mesh_.triangles.push_back({loop_[0], loop_[1], loop_[2]});
    mesh_.triangle_lines.push_back(facet_line_);
    state_ = State::kEndLoop;
  }

  Mesh& mesh_;
  const std::string& name_;
  double unit_m_;
  VertexWelder weld_;
  State state_ = State::kStart;
  std::vector<std::uint32_t> loop_;
  std::size_t facet_line_ = 0;
};

Mesh read_stl_ascii(const std::string& bytes, const std::string& name, double unit_m) {
  Mesh mesh;
  mesh.name = name;
  mesh.unit_m = unit_m;
  StlAsciiReader reader(mesh, name, unit_m);
  std::istringstream in(bytes);
  std::string line;
  std::size_t ln = 0;
  while (std::getline(in, line)) reader.read_line(line, ++ln);
  reader.finish(ln);
  return mesh;
}

Mesh read_stl_binary(const std::string& bytes, const std::string& name, double unit_m) {
  Mesh mesh;
  mesh.name = name;
  mesh.unit_m = unit_m;
  VertexWelder weld(mesh);
  std::uint32_t n = 0;
  std::memcpy(&n, bytes.data() + 80, 4);
  weld.reserve(n);
  mesh.triangles.reserve(n);
  for (std::uint32_t k = 0; k < n; ++k) {
    const char* rec = bytes.data() + 84 + 50 * static_cast<std::size_t>(k);
    std::array<std::uint32_t, 3> idx{};
    for (std::size_t j = 0; j < 3; ++j) {
      float xyz[3];
      std::memcpy(xyz, rec + 12 + 12 * j, 12);
      for (float c : xyz) {
        if (!std::isfinite(c)) {
          throw MeshFormatError(name + ": triangle " + std::to_string(k) + ", vertex " + std::to_string(j) +
                                ": coordinate is not a finite number");
        }
      }
      idx[j] = weld.add(Eigen::Vector3d(xyz[0], xyz[1], xyz[2]) * unit_m);
    }
    mesh.triangles.push_back(idx);
  }
  if (mesh.triangles.empty()) throw MeshFormatError(name + ": binary STL with no triangles");
  return mesh;
}

}  // namespace

Mesh read_obj(std::istream& in, const std::string& name, double unit_m) {
  Mesh mesh;
  mesh.name = name;
  mesh.unit_m = unit_m;
  std::string line;
  std::size_t ln = 0;
  while (std::getline(in, line)) {
    ++ln;
    if (ln == 1 && line.starts_with(kByteOrderMark)) line.erase(0, kByteOrderMark.size());
    if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    const auto tok = split(line);
    if (tok.empty()) continue;
    const std::string& kw = tok[0];
    if (kw == "v") {
      // x y z, x y z w, or x y z r g b (vertex colours, as MeshLab writes them).
      if (tok.size() != 4 && tok.size() != 5 && tok.size() != 7) {
        fail_line(name, ln,
                  "vertex needs 3 coordinates (x y z [w] or x y z r g b), got " + std::to_string(tok.size() - 1));
      }
      Eigen::Vector3d v;
      for (int k = 0; k < 3; ++k) {
        if (!parse_double(tok[k + 1], v[k]) || !std::isfinite(v[k])) {
          fail_line(name, ln, "vertex coordinate '" + tok[k + 1] + "' is not a finite number");
        }
      }
      mesh.vertices.emplace_back(v * unit_m);
    } else if (kw == "f") {
      if (tok.size() < 4) fail_line(name, ln, "face needs at least 3 vertices, got " + std::to_string(tok.size() - 1));
      std::vector<std::uint32_t> poly;
      for (std::size_t k = 1; k < tok.size(); ++k) {
        const std::string head = tok[k].substr(0, tok[k].find('/'));
        long long i = 0;
        auto [p, ec] = std::from_chars(head.data(), head.data() + head.size(), i);
        if (ec != std::errc() || p != head.data() + head.size() || i == 0) {
          fail_line(name, ln, "face vertex '" + tok[k] + "' is not a vertex index (1-based, or negative relative)");
        }
        const auto nv = static_cast<long long>(mesh.vertices.size());
        const long long resolved = i > 0 ? i - 1 : nv + i;
        if (resolved < 0 || resolved >= nv) {
          fail_line(name, ln,
                    "face vertex index " + std::to_string(i) + " is out of range (" + std::to_string(nv) +
                        " vertices defined so far)");
        }
        poly.push_back(static_cast<std::uint32_t>(resolved));
      }
      for (const Triangle& t : triangulate_polygon(mesh.vertices, poly)) {
        mesh.triangles.push_back(t);
        mesh.triangle_lines.push_back(ln);
      }
    } else if (kw == "vt" || kw == "vn" || kw == "vp" || kw == "o" || kw == "g" || kw == "s" || kw == "usemtl" ||
               kw == "mtllib" || kw == "l" || kw == "p") {
      continue;  // texture, normals, groups, materials; lines and points have no volume
    } else {
      fail_line(name, ln, "unknown OBJ statement '" + kw + "' (expected v, f, vt, vn, o, g, s, usemtl, mtllib, l, p)");
    }
  }
  if (mesh.triangles.empty()) throw MeshFormatError(name + ": no faces ('f' lines)");
  return mesh;
}

Mesh read_stl(const std::string& bytes, const std::string& name, double unit_m) {
  if (bytes.size() >= 84) {
    std::uint32_t n = 0;
    std::memcpy(&n, bytes.data() + 80, 4);
    if (bytes.size() == 84 + 50 * static_cast<std::size_t>(n)) return read_stl_binary(bytes, name, unit_m);
  }
  // Not a well-sized binary file: ASCII (keywords in any case, after a byte-order mark if
  // there is one), or a truncated/padded binary one.
  const bool bom = bytes.compare(0, kByteOrderMark.size(), kByteOrderMark) == 0;
  std::size_t first = bytes.find_first_not_of(" \t\r\n", bom ? kByteOrderMark.size() : 0);
  if (first != std::string::npos && lower(bytes.substr(first, 5)) == "solid" &&
      contains_word_any_case(std::string_view(bytes).substr(first, std::size_t{1} << 16), "facet")) {
    return read_stl_ascii(bom ? bytes.substr(kByteOrderMark.size()) : bytes, name, unit_m);
  }
  if (bytes.size() < 84) {
    throw MeshFormatError(name + ": " + std::to_string(bytes.size()) +
                          " bytes: too short for a binary STL header (84 bytes) and not ASCII STL ('solid ...')");
  }
  std::uint32_t n = 0;
  std::memcpy(&n, bytes.data() + 80, 4);
  const std::size_t expected = 84 + 50 * static_cast<std::size_t>(n);
  const std::size_t whole = (bytes.size() - 84) / 50;
  throw MeshFormatError(name + ": binary STL header declares " + std::to_string(n) + " triangles (" +
                        std::to_string(expected) + " bytes) but the file has " + std::to_string(bytes.size()) +
                        " bytes" +
                        (bytes.size() < expected ? " (truncated in triangle " + std::to_string(whole) + ")" : ""));
}

Mesh load_mesh(const std::string& path, double unit_m, LoadReport* report, double weld_m) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read mesh file " + path);
  const std::string ext = lower(path.size() >= 4 ? path.substr(path.size() - 4) : "");
  Mesh mesh;
  if (ext == ".obj") {
    mesh = read_obj(in, path, unit_m);
  } else if (ext == ".stl") {
    std::ostringstream ss;
    ss << in.rdbuf();
    mesh = read_stl(ss.str(), path, unit_m);
  } else {
    throw Error(path + ": unknown mesh format (expected a .obj or .stl file)");
  }
  LoadReport r;
  r.weld = weld_vertices(mesh, weld_m < 0.0 ? default_weld_tolerance(mesh) : weld_m);
  r.needles = drop_needles(mesh);
  if (report) *report = r;
  return mesh;
}

std::string obj_text(const Mesh& mesh, double unit_m) {
  std::ostringstream out;
  out.precision(10);
  out << "# " << mesh.name << " (Poise), units: " << unit_m << " m\n";
  for (const auto& v : mesh.vertices)
    out << "v " << v.x() / unit_m << ' ' << v.y() / unit_m << ' ' << v.z() / unit_m << '\n';
  for (const auto& t : mesh.triangles) out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
  return out.str();
}

std::string stl_bytes(const Mesh& mesh, double unit_m) {
  std::string out;
  out.reserve(84 + 50 * mesh.triangles.size());
  // The 80-byte header: "Poise <name>" (the name up to a NUL, as C text) cut to 79 bytes, NUL-padded.
  std::string header = fmt::format("Poise {}", mesh.name.c_str());
  header.resize(79);
  out.append(header).append(1, '\0');
  const auto n = static_cast<std::uint32_t>(mesh.triangles.size());
  out.append(reinterpret_cast<const char*>(&n), 4);
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
    float rec[12];
    const Eigen::Vector3d nrm = mesh.face_normal(k).normalized();
    for (int j = 0; j < 3; ++j) rec[j] = static_cast<float>(nrm[j]);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j)
        rec[3 + 3 * i + j] = static_cast<float>(mesh.vertices[mesh.triangles[k][i]][j] / unit_m);
    }
    out.append(reinterpret_cast<const char*>(rec), sizeof rec);
    const std::uint16_t attr = 0;
    out.append(reinterpret_cast<const char*>(&attr), 2);
  }
  return out;
}

std::string ascii_stl_text(const Mesh& mesh, double unit_m) {
  std::string out;
  const std::string name = mesh.name.empty() ? "part" : mesh.name;
  out += "solid " + name + '\n';
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
    const Eigen::Vector3d n = mesh.face_normal(k).normalized();
    fmt::format_to(std::back_inserter(out), "  facet normal {:.9g} {:.9g} {:.9g}\n    outer loop\n", n.x(), n.y(),
                   n.z());
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d v = mesh.vertices[mesh.triangles[k][i]] / unit_m;
      fmt::format_to(std::back_inserter(out), "      vertex {:.17g} {:.17g} {:.17g}\n", v.x(), v.y(), v.z());
    }
    out += "    endloop\n  endfacet\n";
  }
  out += "endsolid " + name + '\n';
  return out;
}

namespace {

// The whole file in one write, checked: a refused write or close names the file and the
// system's reason (a full disk: "No space left on device").
void write_whole_file(const std::string& path, const std::string& bytes) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) throw Error(path + ": cannot write: " + std::strerror(errno));
  const bool wrote = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  const int write_errno = errno;
  const bool closed = std::fclose(f) == 0;
  if (!wrote || !closed) throw Error(path + ": cannot write: " + std::strerror(wrote ? errno : write_errno));
}

}  // namespace

void write_obj(const Mesh& mesh, const std::string& path, double unit_m) {
  write_whole_file(path, obj_text(mesh, unit_m));
}

void write_stl(const Mesh& mesh, const std::string& path, double unit_m) {
  write_whole_file(path, stl_bytes(mesh, unit_m));
}

void write_ascii_stl(const Mesh& mesh, const std::string& path, double unit_m) {
  write_whole_file(path, ascii_stl_text(mesh, unit_m));
}

}  // namespace poise::geometry
