#include "estimators/lab_table.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <optional>

#include "core/error.h"
#include "core/format.h"

namespace poise::estimators {
namespace {

std::string trimmed(std::string_view s) {
  std::size_t b = 0, e = s.size();
  while (b < e && (s[b] == ' ' || s[b] == '\t' || s[b] == '\r')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '\r')) --e;
  std::string out(s.substr(b, e - b));
  if (out.size() >= 2 && out.front() == '"' && out.back() == '"') out = out.substr(1, out.size() - 2);
  return out;
}

bool is_comment(const std::string& line) {
  const std::string t = trimmed(line);
  return t.empty() || t[0] == '#' || t[0] == '%' || t.rfind("//", 0) == 0;
}

int line_number(std::size_t line) { return static_cast<int>(std::min<std::size_t>(line, 2147483647u)); }

enum class Delimiter { kComma, kSemicolon, kTab, kWhitespace };

Delimiter delimiter_of(const std::string& header) {
  const auto count = [&](char c) {  // outside double quotes
    long n = 0;
    bool quoted = false;
    for (const char h : header) {
      if (h == '"') quoted = !quoted;
      if (h == c && !quoted) ++n;
    }
    return n;
  };
  const long semicolons = count(';'), tabs = count('\t'), commas = count(',');
  if (semicolons == 0 && tabs == 0 && commas == 0) return Delimiter::kWhitespace;
  if (semicolons >= tabs && semicolons >= commas) return Delimiter::kSemicolon;
  if (tabs >= commas) return Delimiter::kTab;
  return Delimiter::kComma;
}

const char* delimiter_name(Delimiter d) {
  switch (d) {
    case Delimiter::kComma: return "comma";
    case Delimiter::kSemicolon: return "semicolon";
    case Delimiter::kTab: return "tab";
    case Delimiter::kWhitespace: return "whitespace";
  }
  return "comma";
}

std::vector<std::string> cells_of(const std::string& line, Delimiter d) {
  std::vector<std::string> cells;
  if (d == Delimiter::kWhitespace) {
    std::size_t k = 0;
    while (k < line.size()) {
      while (k < line.size() && (line[k] == ' ' || line[k] == '\t' || line[k] == '\r')) ++k;
      if (k >= line.size()) break;
      const std::size_t b = k;
      while (k < line.size() && line[k] != ' ' && line[k] != '\t' && line[k] != '\r') ++k;
      cells.push_back(trimmed(std::string_view(line).substr(b, k - b)));
    }
    return cells;
  }
  // A cell in double quotes may hold the delimiter ("Iq, A") and doubled quotes ("" for ").
  const char sep = d == Delimiter::kComma ? ',' : d == Delimiter::kSemicolon ? ';' : '\t';
  std::string cell;
  bool quoted = false;
  for (std::size_t k = 0; k <= line.size(); ++k) {
    if (k == line.size() || (line[k] == sep && !quoted)) {
      cells.push_back(trimmed(cell));
      cell.clear();
    } else if (line[k] == '"') {
      if (quoted && k + 1 < line.size() && line[k + 1] == '"') {
        cell += '"';
        ++k;
      } else {
        quoted = !quoted;
      }
    } else {
      cell += line[k];
    }
  }
  return cells;
}

std::optional<double> number_of(std::string cell, bool decimal_comma) {
  if (decimal_comma) std::replace(cell.begin(), cell.end(), ',', '.');
  const std::size_t sign = !cell.empty() && cell[0] == '+' ? 1 : 0;
  if (cell.size() <= sign || (sign && cell[1] == '-')) return std::nullopt;
  double v = 0.0;
  const auto res = std::from_chars(cell.data() + sign, cell.data() + cell.size(), v);
  if (res.ec != std::errc() || res.ptr != cell.data() + cell.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

// A date and time as loggers write it, "2024-07-04 11:34:18.818" or "2024-07-04T11:34:18Z" (an
// offset "+02:00" is taken off): seconds since 1970-01-01 00:00 UTC; nullopt for anything else.
std::optional<double> seconds_of_date_time(const std::string& cell) {
  int year = 0, month = 0, day = 0, hour = 0, minute = 0;
  double second = 0.0;
  char sep = 0;
  int used = 0;
  if (std::sscanf(cell.c_str(), "%4d-%2d-%2d%c%2d:%2d:%lf%n", &year, &month, &day, &sep, &hour, &minute, &second,
                  &used) != 7 ||
      (sep != 'T' && sep != ' ') || month < 1 || month > 12 || day < 1 || day > 31 || hour > 23 || minute > 59 ||
      !(second >= 0.0 && second < 61.0)) {
    return std::nullopt;
  }
  double offset = 0.0;
  const std::string rest = cell.substr(static_cast<std::size_t>(used));
  int oh = 0, om = 0;
  if (rest == "Z" || rest.empty()) {
  } else if ((rest[0] == '+' || rest[0] == '-') && std::sscanf(rest.c_str() + 1, "%2d:%2d", &oh, &om) == 2) {
    offset = (rest[0] == '+' ? 1.0 : -1.0) * (oh * 3600.0 + om * 60.0);
  } else {
    return std::nullopt;
  }
  // Days from the civil date (proleptic Gregorian), as in H. Hinnant's days_from_civil.
  const int y = year - (month <= 2 ? 1 : 0);
  const int era = (y >= 0 ? y : y - 399) / 400;
  const int yoe = y - era * 400;
  const int doy = (153 * (month + (month > 2 ? -3 : 9)) + 2) / 5 + day - 1;
  const int doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  const double days = static_cast<double>(era) * 146097.0 + doe - 719468.0;
  return days * 86400.0 + hour * 3600.0 + minute * 60.0 + second - offset;
}

// The unit a header carries: "time [ms]", "Iq (A)", "position_rad"; nullopt when none of them
// is a unit of the dimension.
std::optional<std::string> unit_in_header(const std::string& header, const units::Dimension& dim) {
  std::vector<std::string> candidates;
  for (const auto& [open, close] : {std::pair{'[', ']'}, std::pair{'(', ')'}}) {
    const std::size_t a = header.rfind(open), b = header.rfind(close);
    if (a != std::string::npos && b != std::string::npos && b > a + 1)
      candidates.push_back(trimmed(header.substr(a + 1, b - a - 1)));
  }
  const std::size_t underscore = header.rfind('_');
  if (underscore != std::string::npos && underscore + 1 < header.size())
    candidates.push_back(header.substr(underscore + 1));
  for (const std::string& c : candidates) {
    try {
      column_unit_factor(c, dim);
      return c;
    } catch (const Error&) {
    }
  }
  return std::nullopt;
}

// A unit in the header's brackets that Poise knows but of another dimension than `dim`.
std::optional<std::string> unit_of_other_kind(const std::string& header, const units::Dimension& dim) {
  for (const auto& [open, close] : {std::pair{'[', ']'}, std::pair{'(', ')'}}) {
    const std::size_t a = header.rfind(open), b = header.rfind(close);
    if (a == std::string::npos || b == std::string::npos || b <= a + 1) continue;
    const std::string u = trimmed(header.substr(a + 1, b - a - 1));
    try {
      if (units::parse_quantity("1 " + u).dim != dim) return u;
    } catch (const Error&) {
    }
  }
  return std::nullopt;
}

std::string listed(const std::vector<std::string>& headers) {
  std::string s;
  for (std::size_t i = 0; i < headers.size() && i < 12; ++i) s += (i ? ", '" : "'") + headers[i] + "'";
  if (headers.size() > 12) s += ", ... (" + std::to_string(headers.size()) + " columns)";
  return s;
}

struct Found {
  const ColumnRole* role;
  std::size_t index;
  double factor;
};

// How a header may name a column, in the order they are tried: as written, in another case
// ("Run" for "run"), with its unit added ("amp [mm/s]" for "amp").
enum class HeaderMatch { kExact, kAnyCase, kWithoutUnit };

bool header_matches(const std::string& header, const std::string& name, HeaderMatch how) {
  switch (how) {
    case HeaderMatch::kExact: return header == name;
    case HeaderMatch::kAnyCase:
      return std::equal(header.begin(), header.end(), name.begin(), name.end(),
                        [](unsigned char x, unsigned char y) { return std::tolower(x) == std::tolower(y); });
    case HeaderMatch::kWithoutUnit: {
      const std::size_t bracket = header.find_last_of("[(");
      return bracket != std::string::npos && bracket > 0 && trimmed(header.substr(0, bracket)) == name;
    }
  }
  return false;
}

// The index of a role's column: the header the user named (as written, the last such, or without
// its unit; InputError if the file has none), else a default header (each way in turn).
std::optional<std::size_t> column_index(const ColumnRole& role, const std::vector<std::string>& headers,
                                        const ColumnMapping& mapping, const SourceLocation& where) {
  std::optional<std::size_t> index;
  if (auto it = mapping.header.find(role.role); it != mapping.header.end()) {
    for (std::size_t i = 0; i < headers.size(); ++i) {
      if (header_matches(headers[i], it->second, HeaderMatch::kExact)) index = i;
    }
    for (std::size_t i = 0; i < headers.size() && !index; ++i) {
      if (header_matches(headers[i], it->second, HeaderMatch::kWithoutUnit)) index = i;
    }
    if (!index) {
      throw InputError(where, mapping.naming.empty() ? "--column " + role.role : role.what, it->second,
                       "one of the file's headers: " + listed(headers));
    }
    return index;
  }
  for (const HeaderMatch how : {HeaderMatch::kExact, HeaderMatch::kAnyCase, HeaderMatch::kWithoutUnit}) {
    for (const std::string& h : role.default_headers) {
      for (std::size_t i = 0; i < headers.size() && !index; ++i) {
        if (header_matches(headers[i], h, how)) index = i;
      }
    }
  }
  return index;
}

// The column of a role, and the SI value of one of its units; nullopt for an optional role not
// in the file.
std::optional<Found> find_column(const ColumnRole& role, const std::vector<std::string>& headers,
                                 const ColumnMapping& mapping, const std::string& path, std::size_t header_line,
                                 std::vector<const ColumnRole*>& missing) {
  const SourceLocation where{path, line_number(header_line), 0};
  const bool named = mapping.header.count(role.role) > 0;
  const std::optional<std::size_t> index = column_index(role, headers, mapping, where);
  if (!index) {
    if (role.required) missing.push_back(&role);
    return std::nullopt;
  }
  if (role.text) return Found{&role, *index, 1.0};
  const std::string& header = headers[*index];
  std::string unit;
  if (auto it = mapping.unit.find(role.role); it != mapping.unit.end()) {
    unit = it->second;
  } else if (auto in_header = unit_in_header(header, role.dimension)) {
    unit = *in_header;
  } else if (const auto other = role.unit_by_default ? unit_of_other_kind(header, role.dimension) : std::nullopt) {
    // A declared file whose header names a unit of another kind ("[um]" where the campaign
    // reads velocities): refused, not read in the declared unit.
    throw InputError(where, "unit of column '" + header + "' (" + role.what + ")", *other,
                     "a unit of " + units::dimension_name(role.dimension) + " like the declared " + role.default_unit +
                         " (" + *other + " is " + units::dimension_name(units::parse_quantity("1 " + *other).dim) +
                         "): convert the column or declare its unit");
  } else if (!named || role.unit_by_default ||
             std::find(role.default_headers.begin(), role.default_headers.end(), header) !=
                 role.default_headers.end()) {
    unit = role.default_unit;
  } else {
    throw InputError(where, "unit of column '" + header + "' (" + role.what + ")", "(not given)",
                     "--unit " + role.role + "=UNIT, e.g. --unit " + role.role + "=" + role.default_unit +
                         (role.dimension == units::kAngle
                              ? ", or for encoder counts --unit " + role.role + "=\"1/4096 rev\" (counts a turn)"
                              : std::string()));
  }
  try {
    return Found{&role, *index, column_unit_factor(unit, role.dimension)};
  } catch (const Error& e) {
    std::string expected = e.what();
    if (expected.rfind("expected ", 0) == 0) expected.erase(0, 9);
    throw InputError(where, "unit of column '" + header + "' (" + role.what + ")", unit, expected);
  }
}

// Every required column the file lacks, in one message.
void refuse_missing(const std::vector<const ColumnRole*>& missing, const std::vector<std::string>& headers,
                    const std::string& path, std::size_t header_line, const std::string& naming) {
  if (missing.empty()) return;
  std::string names, options;
  for (std::size_t i = 0; i < missing.size(); ++i) {
    std::string defaults;
    for (const auto& h : missing[i]->default_headers) defaults += (defaults.empty() ? "'" : " or '") + h + "'";
    if (i > 0) names += i + 1 == missing.size() ? " and " : ", ";
    names += fmt::format("{} (the {})", defaults, missing[i]->what);
    if (i > 0) options += ' ';
    if (naming.empty()) options += fmt::format("--column {}=HEADER", missing[i]->role);
  }
  const bool several = missing.size() > 1;
  throw Error(
      fmt::format("{}:{}: missing column{} {}: the file's columns are {}; name the one{} that hold{} {} with {}", path,
                  header_line, several ? "s" : "", names, listed(headers), several ? "s" : "", several ? "" : "s",
                  several ? "them" : "it", naming.empty() ? options : naming));
}

}  // namespace

double column_unit_factor(const std::string& text, const units::Dimension& dim) {
  const std::string t = trimmed(text);
  const std::string expected = "a unit of " + units::dimension_name(dim) + " (e.g. \"" + units::example_unit(dim) +
                               "\"), one count as a quantity (\"0.5 " + units::example_unit(dim) +
                               "\") or a fraction (\"1/4096 rev\")";
  // "1/4096 rev": a fraction of a unit.
  if (const std::size_t slash = t.find('/'), space = t.find(' ');
      slash != std::string::npos && space != std::string::npos && slash < space) {
    const auto num = number_of(t.substr(0, slash), false);
    const auto den = number_of(t.substr(slash + 1, space - slash - 1), false);
    if (num && den && *den != 0.0) return *num / *den * column_unit_factor(t.substr(space + 1), dim);
  }
  units::Quantity q;
  try {
    q = units::parse_quantity(
        std::isdigit(static_cast<unsigned char>(t.empty() ? 'x' : t[0])) || t.rfind('.', 0) == 0 ? t : "1 " + t);
  } catch (const Error&) {
    throw Error("expected " + expected);
  }
  require(q.dim == dim, "expected " + expected + ", got " + units::dimension_name(q.dim));
  require(std::isfinite(q.value) && q.value != 0.0, "expected " + expected + " (not zero)");
  return q.value;
}

void add_column_option(ColumnMapping& mapping, const std::string& option, const std::string& text,
                       const std::vector<ColumnRole>& roles) {
  const std::size_t eq = text.find('=');
  std::string known;
  for (const auto& r : roles) known += (known.empty() ? "" : ", ") + r.role;
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size()) {
    throw InputError({"(command line)", 0, 0}, option, text, "ROLE=VALUE with ROLE one of " + known);
  }
  const std::string role = trimmed(text.substr(0, eq));
  const bool exists = std::any_of(roles.begin(), roles.end(), [&](const ColumnRole& r) { return r.role == role; });
  if (!exists) throw InputError({"(command line)", 0, 0}, option, text, "a role among " + known);
  (option == "--unit" ? mapping.unit : mapping.header)[role] = trimmed(text.substr(eq + 1));
}

namespace {

// A NumPy .npy file (format 1.x/2.x; little-endian float64, float32, int64 or int32; C or
// Fortran order): a 1-D array is one column, a 2-D array of shape (a, b) holds min(a, b)
// series of max(a, b) values (a logger's np.save of [t, pos, i] or of rows of them). The
// columns are named by their index, "0", "1", ...; rows are numbered from 1 (there is no line).
struct NpyArray {
  std::vector<std::vector<double>> columns;
};

NpyArray read_npy(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open the file");
  char magic[8] = {};
  in.read(magic, 8);
  require(in && std::string(magic, 6) == "\x93NUMPY", path + ": not a NumPy .npy file (no \\x93NUMPY magic)");
  const int major = static_cast<unsigned char>(magic[6]);
  std::size_t header_length = 0;
  unsigned char len[4] = {};
  in.read(reinterpret_cast<char*>(len), major == 1 ? 2 : 4);
  header_length = len[0] | (static_cast<std::size_t>(len[1]) << 8);
  if (major != 1) header_length |= (static_cast<std::size_t>(len[2]) << 16) | (static_cast<std::size_t>(len[3]) << 24);
  std::string header(header_length, ' ');
  in.read(header.data(), static_cast<std::streamsize>(header_length));
  require(static_cast<bool>(in), path + ": the .npy header is cut short");
  auto field = [&](const std::string& key) {
    const std::size_t at = header.find("'" + key + "'");
    require(at != std::string::npos, path + ": the .npy header has no '" + key + "'");
    return header.substr(header.find(':', at) + 1);
  };
  const std::string descr = field("descr");
  const std::size_t q1 = descr.find('\''), q2 = descr.find('\'', q1 + 1);
  const std::string type = descr.substr(q1 + 1, q2 - q1 - 1);
  const bool fortran = field("fortran_order").find("True") < field("fortran_order").find(',');
  const std::string shape_text = field("shape");
  std::vector<std::size_t> shape;
  for (std::size_t k = shape_text.find('(') + 1; k < shape_text.size() && shape_text[k] != ')'; ++k) {
    if (std::isdigit(static_cast<unsigned char>(shape_text[k]))) {
      std::size_t end = k;
      while (end < shape_text.size() && std::isdigit(static_cast<unsigned char>(shape_text[end]))) ++end;
      shape.push_back(std::stoul(shape_text.substr(k, end - k)));
      k = end;
    }
  }
  require(shape.size() == 1 || shape.size() == 2,
          path + ": a .npy array of " + std::to_string(shape.size()) + " dimensions; expected 1 (one column) or 2");
  const std::size_t width = type == "<f8" || type == "<i8" ? 8 : type == "<f4" || type == "<i4" ? 4 : 0;
  require(width > 0,
          path + ": .npy values of type '" + type + "'; expected little-endian float64, float32, int64 or int32");
  const std::size_t rows = shape[0], cols = shape.size() == 2 ? shape[1] : 1;
  std::vector<double> flat(rows * cols);
  std::vector<char> bytes(width);
  for (double& v : flat) {
    in.read(bytes.data(), static_cast<std::streamsize>(width));
    require(static_cast<bool>(in),
            path + ": the .npy data end before its shape's " + std::to_string(rows * cols) + " values");
    if (type == "<f8") {
      std::memcpy(&v, bytes.data(), 8);
    } else if (type == "<f4") {
      float f = 0;
      std::memcpy(&f, bytes.data(), 4);
      v = f;
    } else if (type == "<i8") {
      std::int64_t i = 0;
      std::memcpy(&i, bytes.data(), 8);
      v = static_cast<double>(i);
    } else {
      std::int32_t i = 0;
      std::memcpy(&i, bytes.data(), 4);
      v = i;
    }
  }
  auto at = [&](std::size_t r, std::size_t c) { return fortran ? flat[c * rows + r] : flat[r * cols + c]; };
  NpyArray a;
  const bool series_are_rows = cols > rows;  // shape (3, 4306): three series
  const std::size_t series = series_are_rows ? rows : cols, length = series_are_rows ? cols : rows;
  a.columns.assign(series, std::vector<double>(length));
  for (std::size_t s = 0; s < series; ++s) {
    for (std::size_t k = 0; k < length; ++k) a.columns[s][k] = series_are_rows ? at(s, k) : at(k, s);
  }
  return a;
}

bool is_npy(const std::string& path) { return path.size() > 4 && path.compare(path.size() - 4, 4, ".npy") == 0; }

// A .npy array's series as the table's columns, named "0", "1", ... (no lines: rows from 1).
LabTable npy_table(const std::string& path, const std::vector<ColumnRole>& roles, const ColumnMapping& mapping) {
  LabTable t;
  t.file = path;
  const NpyArray a = read_npy(path);
  std::vector<std::string> headers;
  for (std::size_t c = 0; c < a.columns.size(); ++c) headers.push_back(std::to_string(c));
  t.delimiter = "NumPy .npy";
  t.header_line = 0;
  std::vector<const ColumnRole*> missing;
  for (const ColumnRole& role : roles) {
    if (auto f = find_column(role, headers, mapping, path, 0, missing)) {
      require(!role.text, path + ": a NumPy array holds numbers only; the " + role.what + " needs a text table");
      t.header[role.role] = headers[f->index];
      t.unit[role.role] = mapping.unit.count(role.role) ? mapping.unit.at(role.role) : role.default_unit;
      auto& values = t.si[role.role];
      for (double v : a.columns[f->index]) {
        require(std::isfinite(v),
                path + ": column " + headers[f->index] + " (" + role.what + ") holds a value that is not finite");
        values.push_back(v * f->factor);
      }
    }
  }
  refuse_missing(missing, headers, path, 0, mapping.naming);
  const std::size_t n = a.columns.empty() ? 0 : a.columns.front().size();
  for (std::size_t k = 0; k < n; ++k) t.lines.push_back(k + 1);
  return t;
}

}  // namespace

LabTable read_lab_table(const std::string& path, const std::vector<ColumnRole>& roles, const ColumnMapping& mapping) {
  LabTable t;
  t.file = path;
  if (is_npy(path)) return npy_table(path, roles, mapping);
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open the file");
  std::string line;
  std::size_t lineno = 0;
  std::vector<std::string> headers;
  Delimiter delimiter = Delimiter::kComma;
  while (std::getline(in, line)) {
    ++lineno;
    if (lineno == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    if (is_comment(line)) continue;
    delimiter = delimiter_of(line);
    headers = cells_of(line, delimiter);
    break;
  }
  if (headers.empty()) throw Error(path + ": no header line (the first line that is not a comment names the columns)");
  t.header_line = lineno;
  t.delimiter = delimiter_name(delimiter);
  const bool decimal_comma = delimiter == Delimiter::kSemicolon || delimiter == Delimiter::kTab;
  std::vector<Found> found;
  std::vector<const ColumnRole*> missing;
  for (const ColumnRole& role : roles) {
    if (auto f = find_column(role, headers, mapping, path, lineno, missing)) {
      found.push_back(*f);
      t.header[role.role] = headers[f->index];
      if (role.text) {
        t.text[role.role];
        continue;
      }
      t.unit[role.role] = mapping.unit.count(role.role)
                              ? mapping.unit.at(role.role)
                              : unit_in_header(headers[f->index], role.dimension).value_or(role.default_unit);
      t.si[role.role];
    }
  }
  refuse_missing(missing, headers, path, lineno, mapping.naming);
  while (std::getline(in, line)) {
    ++lineno;
    if (is_comment(line)) continue;
    std::vector<std::string> cells = cells_of(line, delimiter);
    while (cells.size() > headers.size() && cells.back().empty()) cells.pop_back();  // a trailing delimiter
    if (cells.size() > headers.size()) {
      throw Error(fmt::format("{}:{}: {} cells, the header (line {}) has {} (delimited by {})", path, lineno,
                              cells.size(), t.header_line, headers.size(), t.delimiter));
    }
    for (const Found& f : found) {
      const std::string& header = headers[f.index];
      if (f.index >= cells.size()) {
        throw InputError({path, line_number(lineno), static_cast<int>(f.index + 1)}, "column " + header,
                         "(missing: " + std::to_string(cells.size()) + " cells in the row)",
                         std::to_string(headers.size()) + " cells, as the header (line " +
                             std::to_string(t.header_line) + ") has, delimited by " + t.delimiter);
      }
      if (f.role->text) {
        t.text[f.role->role].push_back(cells[f.index]);
        continue;
      }
      auto v = number_of(cells[f.index], decimal_comma);
      if (!v && f.role->dimension == units::kTime) {  // a date and time: seconds, whatever the column's unit
        if (const auto s = seconds_of_date_time(cells[f.index])) v = *s / f.factor;
      }
      if (!v) {
        throw InputError(
            {path, line_number(lineno), static_cast<int>(f.index + 1)}, "column " + header,
            cells[f.index].empty() ? "(empty)" : cells[f.index],
            f.role->dimension == units::kTime
                ? "a finite number, or a date and time such as 2024-07-04 11:34:18.818 (the " + f.role->what + ")"
                : "a finite number (the " + f.role->what + ")");
      }
      t.si[f.role->role].push_back(*v * f.factor);
    }
    t.lines.push_back(lineno);
  }
  return t;
}

}  // namespace poise::estimators
