#include <meshless_tools/file_checks.h>

#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <vector>

namespace meshless_tools {

namespace {

using Tokens = std::vector<std::string>;

/** Headers are small: a file whose header does not end within this many bytes is
  * not one (and a file of random bytes is not read whole to find out). */
constexpr std::size_t kMaxHeaderBytes = 1 << 20;

Tokens
split (const std::string& line)
{
  Tokens tokens;
  std::size_t at = 0;
  while ((at = line.find_first_not_of (" \t\r", at)) != std::string::npos) {
    const std::size_t end = line.find_first_of (" \t\r", at);
    tokens.push_back (line.substr (at, end - at));
    at = end;
  }
  return tokens;
}

/** A whole token of decimal digits, at most `max`. */
bool
parseCount (const std::string& token, std::uint64_t max, std::uint64_t& value)
{
  if (token.empty () || token.size () > 20 ||
      token.find_first_not_of ("0123456789") != std::string::npos)
    return false;
  errno = 0;
  const unsigned long long parsed = std::strtoull (token.c_str (), nullptr, 10);
  if (errno == ERANGE || parsed > max)
    return false;
  value = parsed;
  return true;
}

bool
isNumber (const std::string& token)
{
  char* end = nullptr;
  std::strtod (token.c_str (), &end);
  return !token.empty () && end == token.c_str () + token.size ();
}

/** Control bytes other than tab and carriage return: binary data, not a header. */
bool
isText (const std::string& line)
{
  for (const unsigned char c : line)
    if ((c < 0x20 && c != '\t' && c != '\r') || c == 0x7f)
      return false;
  return true;
}

/** The file's header lines (split, comments left out) up to and including the first
  * whose first token is `last`; the data starts at `data_offset`. */
struct Header
{
  std::vector<Tokens> lines;
  std::uint64_t data_offset = 0;
  std::uint64_t file_size = 0;
};

std::string
readHeader (std::ifstream& in, const std::set<std::string>& comments, const char* last,
            Header& header)
{
  in.seekg (0, std::ios::end);
  header.file_size = static_cast<std::uint64_t> (in.tellg ());
  in.seekg (0);
  std::string bytes (std::min<std::uint64_t> (header.file_size, kMaxHeaderBytes), '\0');
  in.read (&bytes[0], static_cast<std::streamsize> (bytes.size ()));
  if (!in)
    return "cannot read the header";
  std::size_t at = 0, number = 0;
  while (at < bytes.size ()) {
    const std::size_t newline = bytes.find ('\n', at);
    const std::size_t end = newline == std::string::npos ? bytes.size () : newline;
    const std::string line = bytes.substr (at, end - at);
    at = newline == std::string::npos ? bytes.size () : newline + 1;
    ++number;
    Tokens tokens = split (line);
    if (tokens.empty () || comments.count (tokens[0]) || tokens[0][0] == '#')
      continue;
    if (!isText (line))
      return "header line " + std::to_string (number) + " holds binary bytes (not a " +
             (comments.count ("comment") ? "PLY" : "PCD") + " file?)";
    const bool is_last = tokens[0] == last;
    header.lines.push_back (std::move (tokens));
    if (is_last) {
      header.data_offset = at;
      return "";
    }
  }
  return std::string ("the header has no ") + last + " line";
}

// ------------------------------------------------------------------------------ PCD

struct PcdLayout
{
  Tokens fields;
  std::vector<std::uint64_t> sizes, counts;
  std::string types;
  std::uint64_t width = 0, height = 0, points = 0;
  std::string data;
};

std::string
parsePcdLine (const Tokens& line, PcdLayout& pcd)
{
  const std::string& key = line[0];
  const Tokens values (line.begin () + 1, line.end ());
  const auto one_count = [&] (std::uint64_t& value) -> std::string {
    if (values.size () != 1 ||
        !parseCount (values[0], std::numeric_limits<std::uint32_t>::max (), value))
      return key + " needs one whole number below 2^32";
    return "";
  };
  if (key == "VERSION")
    return "";
  if (key == "FIELDS" || key == "COLUMNS") {
    pcd.fields = values;
    return values.empty () ? "FIELDS names no field" : "";
  }
  if (key == "SIZE" || key == "COUNT") {
    auto& list = key == "SIZE" ? pcd.sizes : pcd.counts;
    for (const auto& value : values) {
      std::uint64_t n = 0;
      if (!parseCount (value, 1u << 20, n) || n == 0 ||
          (key == "SIZE" && n != 1 && n != 2 && n != 4 && n != 8))
        return key + " value '" + value + "' is not " +
               (key == "SIZE" ? "1, 2, 4 or 8" : "a count from 1 to 2^20");
      list.push_back (n);
    }
    return "";
  }
  if (key == "TYPE") {
    for (const auto& value : values) {
      if (value != "I" && value != "U" && value != "F")
        return "TYPE value '" + value + "' is not I, U or F";
      pcd.types += value;
    }
    return "";
  }
  if (key == "WIDTH")
    return one_count (pcd.width);
  if (key == "HEIGHT")
    return one_count (pcd.height);
  if (key == "POINTS")
    return one_count (pcd.points);
  if (key == "VIEWPOINT") {
    for (const auto& value : values)
      if (!isNumber (value))
        return "VIEWPOINT value '" + value + "' is not a number";
    return values.size () == 7 ? "" : "VIEWPOINT needs 7 numbers";
  }
  if (key == "DATA") {
    if (values.size () == 1 &&
        (values[0] == "ascii" || values[0] == "binary" || values[0] == "binary_compressed")) {
      pcd.data = values[0];
      return "";
    }
    return "DATA is not ascii, binary or binary_compressed";
  }
  return "unknown header line '" + key.substr (0, 40) + "' (not a PCD file?)";
}

/** Every field has a size, a type and a count; the point size and count agree. */
std::string
checkPcdLayout (const PcdLayout& pcd, std::uint64_t& point_size)
{
  if (pcd.fields.empty ())
    return "the header has no FIELDS line";
  const std::size_t n = pcd.fields.size ();
  std::vector<std::uint64_t> counts = pcd.counts;
  if (counts.empty ())
    counts.assign (n, 1);
  if (pcd.sizes.size () != n || pcd.types.size () != n || counts.size () != n)
    return std::to_string (n) + " FIELDS but " + std::to_string (pcd.sizes.size ()) +
           " SIZE, " + std::to_string (pcd.types.size ()) + " TYPE and " +
           std::to_string (counts.size ()) + " COUNT values";
  point_size = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (pcd.types[i] == 'F' && pcd.sizes[i] != 4 && pcd.sizes[i] != 8)
      return "field " + pcd.fields[i] + " is F of size " + std::to_string (pcd.sizes[i]) +
             " (4 or 8 only)";
    point_size += pcd.sizes[i] * counts[i];
  }
  if (point_size > std::numeric_limits<std::uint32_t>::max ())
    return "the point size is 2^32 bytes or more";
  if (pcd.width * pcd.height != pcd.points)
    return "WIDTH * HEIGHT is " + std::to_string (pcd.width * pcd.height) + ", POINTS " +
           std::to_string (pcd.points);
  return "";
}

std::string
checkPcdAscii (std::ifstream& in, const Header& header, const PcdLayout& pcd)
{
  std::uint64_t values = 0;
  for (std::size_t i = 0; i < pcd.fields.size (); ++i)
    values += pcd.counts.empty () ? 1 : pcd.counts[i];
  in.clear ();
  in.seekg (static_cast<std::streamoff> (header.data_offset));
  std::string line;
  std::uint64_t rows = 0;
  while (rows < pcd.points && std::getline (in, line)) {
    const Tokens tokens = split (line);
    if (tokens.empty ())
      continue;
    ++rows;
    bool numbers = tokens.size () == values;
    for (std::size_t i = 0; numbers && i < tokens.size (); ++i)
      numbers = isNumber (tokens[i]);
    if (!numbers)
      return "data line " + std::to_string (rows) + " is not " + std::to_string (values) +
             " numbers";
  }
  if (rows < pcd.points)
    return "POINTS is " + std::to_string (pcd.points) + " but the data has " +
           std::to_string (rows) + " lines";
  return "";
}

std::string
checkPcdBinary (std::ifstream& in, const Header& header, const PcdLayout& pcd,
                std::uint64_t point_size)
{
  const std::uint64_t available = header.file_size - header.data_offset;
  const std::uint64_t needed = pcd.points * point_size;
  if (pcd.data == "binary") {
    if (needed > available)
      return std::to_string (pcd.points) + " points of " + std::to_string (point_size) +
             " bytes need " + std::to_string (needed) + " bytes of data, the file has " +
             std::to_string (available);
    return "";
  }
  // binary_compressed: the compressed and the uncompressed size, then the block.
  unsigned char sizes[8];
  in.clear ();
  in.seekg (static_cast<std::streamoff> (header.data_offset));
  if (available < 8 || !in.read (reinterpret_cast<char*> (sizes), 8))
    return "the compressed data has no sizes (file truncated)";
  std::uint64_t compressed = 0, uncompressed = 0;
  for (int b = 3; b >= 0; --b) {
    compressed = compressed << 8 | sizes[b];
    uncompressed = uncompressed << 8 | sizes[4 + b];
  }
  if (uncompressed != needed)
    return "the compressed data unpacks to " + std::to_string (uncompressed) +
           " bytes, " + std::to_string (pcd.points) + " points of " +
           std::to_string (point_size) + " bytes are " + std::to_string (needed);
  if (compressed > available - 8)
    return "the compressed data has " + std::to_string (compressed) +
           " bytes, the file has " + std::to_string (available - 8) + " (file truncated)";
  return "";
}

// ------------------------------------------------------------------------------ PLY

struct PlyProperty
{
  std::string name;
  std::string type;           // the scalar's type name; empty for a list
  std::size_t size = 0;       // the scalar's, or the list's items'
  std::size_t count_size = 0; // the list's length field; 0 for a scalar
  bool count_signed = false;
};

struct PlyElement
{
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyLayout
{
  std::string format;
  std::vector<PlyElement> elements;
};

std::size_t
plyTypeSize (const std::string& type)
{
  static const std::map<std::string, std::size_t> sizes = {
      {"char", 1},  {"int8", 1},   {"uchar", 1},  {"uint8", 1},   {"short", 2},
      {"int16", 2}, {"ushort", 2}, {"uint16", 2}, {"int", 4},     {"int32", 4},
      {"uint", 4},  {"uint32", 4}, {"float", 4},  {"float32", 4}, {"double", 8},
      {"float64", 8}};
  const auto found = sizes.find (type);
  return found == sizes.end () ? 0 : found->second;
}

std::string
parsePlyLine (const Tokens& line, PlyLayout& ply)
{
  const std::string& key = line[0];
  if (key == "format") {
    if (line.size () != 3 || line[2] != "1.0" ||
        (line[1] != "ascii" && line[1] != "binary_little_endian" &&
         line[1] != "binary_big_endian"))
      return "format is not ascii, binary_little_endian or binary_big_endian 1.0";
    ply.format = line[1];
    return "";
  }
  if (key == "element") {
    PlyElement element;
    if (line.size () != 3 ||
        !parseCount (line[2], std::numeric_limits<std::uint32_t>::max (), element.count))
      return "an element line is not 'element NAME COUNT' with COUNT below 2^32";
    element.name = line[1];
    ply.elements.push_back (element);
    return "";
  }
  if (key == "property") {
    if (ply.elements.empty ())
      return "a property before any element";
    PlyProperty property;
    if (line.size () == 3) {
      property.size = plyTypeSize (line[1]);
      property.type = line[1];
    }
    else if (line.size () == 5 && line[1] == "list") {
      property.count_size = plyTypeSize (line[2]);
      property.count_signed = line[2].find ('u') == std::string::npos;
      property.size = plyTypeSize (line[3]);
      if (line[2].find ("float") != std::string::npos || line[2] == "double")
        property.count_size = 0;
      if (property.count_size == 0)
        property.size = 0;
    }
    if (property.size == 0)
      return "property line '" + (line.size () > 1 ? line[1].substr (0, 20) : std::string ()) +
             " ...' has an unknown type";
    property.name = line.back ();
    ply.elements.back ().properties.push_back (property);
    return "";
  }
  if (key == "end_header")
    return ply.format.empty () ? "the header has no format line" : "";
  return "unknown header line '" + key.substr (0, 40) + "' (not a PLY file?)";
}

bool
isUchar (const PlyProperty& property)
{
  return property.type == "uchar" || property.type == "uint8";
}

/** PCL's reader trusts the vertex layout: it sizes a vertex list from the first
  * vertex, and packs uchar colours into one field written when blue arrives. Layouts
  * it would read past its buffer (or read wrongly) are refused here instead. */
std::string
checkPlyVertexLayout (const PlyLayout& ply)
{
  std::set<std::string> names;
  for (const PlyElement& element : ply.elements)
    if (!names.insert (element.name).second)
      return "element " + element.name.substr (0, 40) + " is declared twice";
  for (const PlyElement& element : ply.elements) {
    if (element.name != "vertex")
      continue;
    const std::vector<PlyProperty>& properties = element.properties;
    for (std::size_t i = 0; i < properties.size (); ++i) {
      const PlyProperty& property = properties[i];
      if (property.count_size)
        return "vertex property " + property.name.substr (0, 40) +
               " is a list (vertex lists are not read)";
      if (!isUchar (property))
        continue;
      const auto named = [&] (std::size_t at, const std::string& name) {
        return at < properties.size () && isUchar (properties[at]) &&
               properties[at].name == name;
      };
      const auto colours_at = [&] (std::size_t at, std::size_t after_red) {
        if (after_red > at)
          return false;
        for (const std::string prefix : {"", "diffuse_"})
          if (named (at - after_red, prefix + "red") && named (at - after_red + 1, prefix + "green") &&
              named (at - after_red + 2, prefix + "blue"))
            return true;
        return false;
      };
      for (const std::string prefix : {"", "diffuse_"})
        if ((property.name == prefix + "red" && !colours_at (i, 0)) ||
            (property.name == prefix + "green" && !colours_at (i, 1)) ||
            (property.name == prefix + "blue" && !colours_at (i, 2)))
          return "vertex colours are not uchar red, green, blue in that order";
      if (property.name == "alpha" && !colours_at (i, 3))
        return "vertex alpha does not follow uchar red, green, blue";
    }
  }
  return "";
}

/** An integer of `size` bytes in the file's byte order, or -1 if negative. */
std::int64_t
readLength (const unsigned char* at, std::size_t size, bool is_signed, bool big_endian)
{
  std::uint64_t value = 0;
  for (std::size_t b = 0; b < size; ++b)
    value = value << 8 | at[big_endian ? b : size - 1 - b];
  const bool negative = is_signed && (value >> (8 * size - 1)) & 1;
  return negative ? -1 : static_cast<std::int64_t> (value);
}

std::string
checkPlyBinary (std::ifstream& in, const Header& header, const PlyLayout& ply)
{
  const bool big_endian = ply.format == "binary_big_endian";
  const std::uint64_t end = header.file_size;
  std::uint64_t at = header.data_offset;
  std::vector<unsigned char> length (8);
  for (const PlyElement& element : ply.elements) {
    const auto truncated = [&] (std::uint64_t instance) {
      return "element " + element.name.substr (0, 40) + " " + std::to_string (instance) +
             " of " + std::to_string (element.count) + " lies past the end of the file";
    };
    std::uint64_t fixed = 0;
    bool has_list = false;
    for (const PlyProperty& property : element.properties) {
      fixed += property.count_size == 0 ? property.size : 0;
      has_list = has_list || property.count_size > 0;
    }
    if (!has_list) {
      if (fixed * element.count > end - at)
        return truncated ((end - at) / std::max<std::uint64_t> (fixed, 1));
      at += fixed * element.count;
      continue;
    }
    for (std::uint64_t i = 0; i < element.count; ++i)
      for (const PlyProperty& property : element.properties) {
        const std::uint64_t scalar = property.count_size ? property.count_size : property.size;
        if (scalar > end - at)
          return truncated (i);
        if (property.count_size) {
          in.clear ();
          in.seekg (static_cast<std::streamoff> (at));
          in.read (reinterpret_cast<char*> (length.data ()),
                   static_cast<std::streamsize> (scalar));
          const std::int64_t items =
              readLength (length.data (), scalar, property.count_signed, big_endian);
          if (!in || items < 0)
            return "a list of element " + element.name.substr (0, 40) +
                   " has a negative length";
          at += scalar;
          if (static_cast<std::uint64_t> (items) * property.size > end - at)
            return truncated (i);
          at += static_cast<std::uint64_t> (items) * property.size;
        }
        else
          at += scalar;
      }
  }
  return "";
}

std::string
checkPlyAscii (std::ifstream& in, const Header& header, const PlyLayout& ply)
{
  in.clear ();
  in.seekg (static_cast<std::streamoff> (header.data_offset));
  std::string line;
  for (const PlyElement& element : ply.elements)
    for (std::uint64_t i = 0; i < element.count; ++i) {
      Tokens tokens;
      while (tokens.empty () && std::getline (in, line))
        tokens = split (line);
      const std::string where =
          "element " + element.name.substr (0, 40) + " " + std::to_string (i);
      if (tokens.empty ())
        return where + " of " + std::to_string (element.count) +
               " lies past the end of the file";
      std::size_t token = 0;
      for (const PlyProperty& property : element.properties) {
        std::uint64_t items = 0;
        if (property.count_size &&
            (token >= tokens.size () ||
             !parseCount (tokens[token], tokens.size () - token - 1, items)))
          return where + ": a list length is not a count of the values after it";
        token += 1 + items;
        if (token > tokens.size ())
          return where + " has fewer values than its properties";
      }
    }
  return "";
}

} // namespace

/** PCL's header parser reads on after the DATA line while lines are empty, comments
  * or start with a header keyword: data that begins so would be taken for header
  * lines (new fields, a new data offset). Such data is refused. */
std::string
checkPcdDataStart (std::ifstream& in, const Header& header)
{
  static const char* const keywords[] = {"VERSION", "FIELDS", "COLUMNS", "SIZE",
                                         "TYPE",    "COUNT",  "WIDTH",   "HEIGHT",
                                         "VIEWPOINT", "POINTS", "DATA"};
  in.clear ();
  in.seekg (static_cast<std::streamoff> (header.data_offset));
  std::string line;
  while (std::getline (in, line)) {
    const std::size_t first = line.find_first_not_of (" \t\r");
    if (first == std::string::npos || line[first] == '#')
      continue;
    for (const char* keyword : keywords)
      if (line.compare (first, std::string (keyword).size (), keyword) == 0)
        return std::string ("the data starts with the header keyword ") + keyword +
               " (PCL's reader would take it for a header line)";
    return "";
  }
  return "";
}

std::string
checkPcdFile (const std::string& path)
{
  std::ifstream in (path, std::ios::binary);
  if (!in)
    return "cannot open the file";
  Header header;
  std::string error = readHeader (in, {}, "DATA", header);
  PcdLayout pcd;
  std::set<std::string> seen;
  for (std::size_t i = 0; error.empty () && i < header.lines.size (); ++i) {
    const std::string key = header.lines[i][0] == "COLUMNS" ? "FIELDS" : header.lines[i][0];
    if (!seen.insert (key).second)
      return "the header has two " + key + " lines";
    error = parsePcdLine (header.lines[i], pcd);
  }
  if (!error.empty ())
    return error;
  for (const char* key : {"WIDTH", "HEIGHT", "POINTS"})
    if (!seen.count (key))
      return std::string ("the header has no ") + key + " line";
  std::uint64_t point_size = 0;
  error = checkPcdLayout (pcd, point_size);
  if (error.empty ())
    error = checkPcdDataStart (in, header);
  if (!error.empty ())
    return error;
  return pcd.data == "ascii" ? checkPcdAscii (in, header, pcd)
                             : checkPcdBinary (in, header, pcd, point_size);
}

std::string
checkPlyFile (const std::string& path)
{
  std::ifstream in (path, std::ios::binary);
  if (!in)
    return "cannot open the file";
  std::string magic (4, '\0');
  if (!in.read (&magic[0], 4) || (magic != "ply\n" && magic != "ply\r"))
    return "the file does not start with 'ply' (not a PLY file)";
  Header header;
  std::string error = readHeader (in, {"comment", "obj_info"}, "end_header", header);
  PlyLayout ply;
  for (std::size_t i = 1; error.empty () && i < header.lines.size (); ++i)
    error = parsePlyLine (header.lines[i], ply);
  if (error.empty ())
    error = checkPlyVertexLayout (ply);
  if (!error.empty ())
    return error;
  return ply.format == "ascii" ? checkPlyAscii (in, header, ply)
                               : checkPlyBinary (in, header, ply);
}

} // namespace meshless_tools
