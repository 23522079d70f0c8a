// PLY reader: ascii (one record per line), binary_little_endian and binary_big_endian. Reads the
// vertex element's x, y, z, the face element's vertex_indices (or vertex_index) list and the
// tristrips element's vertex_indices strips (-1 restarts); other elements and properties are
// walked over. Values keep the precision of their declared type.
#include <bit>
#include <cstring>
#include <vector>

#include "io/mesh_soup.hpp"
#include "io/text_scan.hpp"

namespace depath::io {

namespace {

enum class Type { int8, uint8, int16, uint16, int32, uint32, float32, float64, none };

Type type_from_name(std::string_view n) {
  if (n == "char" || n == "int8") return Type::int8;
  if (n == "uchar" || n == "uint8") return Type::uint8;
  if (n == "short" || n == "int16") return Type::int16;
  if (n == "ushort" || n == "uint16") return Type::uint16;
  if (n == "int" || n == "int32") return Type::int32;
  if (n == "uint" || n == "uint32") return Type::uint32;
  if (n == "float" || n == "float32") return Type::float32;
  if (n == "double" || n == "float64") return Type::float64;
  return Type::none;
}

int type_size(Type t) {
  switch (t) {
    case Type::int8:
    case Type::uint8:
      return 1;
    case Type::int16:
    case Type::uint16:
      return 2;
    case Type::int32:
    case Type::uint32:
    case Type::float32:
      return 4;
    case Type::float64:
      return 8;
    case Type::none:
      break;
  }
  return 0;
}

struct Property {
  std::string name;
  Type type = Type::none;        // scalar type, or list item type
  Type count_type = Type::none;  // != none for a list
};

struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> properties;
  uint64_t min_record_bytes() const {
    uint64_t n = 0;
    for (const auto& p : properties)
      n += p.count_type == Type::none ? type_size(p.type) : type_size(p.count_type);
    return n;
  }
};

// Reads the values of one record after another, from ascii lines or from binary data.
class RecordReader {
 public:
  RecordReader(std::string_view bytes, size_t start, bool ascii, bool big_endian, SoupBuilder& soup)
      : bytes_(bytes),
        pos_(start),
        ascii_(ascii),
        big_(big_endian),
        lines_(bytes, start),
        tokens_({}),
        soup_(soup) {}

  uint64_t bytes_left() const { return ascii_ ? lines_.bytes_left() : bytes_.size() - pos_; }

  void begin(const Element& e, uint64_t record) {
    element_ = &e;
    record_ = record;
    if (!ascii_) return;
    std::string_view line, token;
    do {
      if (!lines_.next(line))
        soup_.truncated("the file ends at element '" + e.name + "' record " + std::to_string(record) +
                        " of " + std::to_string(e.count));
    } while (!Tokens(line).next(token));
    tokens_ = Tokens(line);
  }

  std::string where() const {
    std::string w = "element '" + element_->name + "' record " + std::to_string(record_);
    return ascii_ ? w + ", " + lines_.where() : w;
  }

  // One value of type `t`, or nullopt when the record (ascii line) or the data (binary) ends.
  std::optional<double> value(Type t) {
    if (ascii_) {
      std::string_view token;
      if (!tokens_.next(token)) return std::nullopt;
      if (t == Type::float32 || t == Type::float64) {
        const auto x = parse_real(token, t == Type::float32);
        if (!x) soup_.fail("has a value " + quoted(token) + " that is not a number (" + where() + ")");
        return x;
      }
      const auto n = parse_integer(token);
      if (!n) soup_.fail("has a value " + quoted(token) + " that is not an integer (" + where() + ")");
      return static_cast<double>(*n);
    }
    const int size = type_size(t);
    if (pos_ + size > bytes_.size()) return std::nullopt;
    unsigned char b[8];
    std::memcpy(b, bytes_.data() + pos_, size);
    pos_ += size;
    if (big_ != (std::endian::native == std::endian::big)) {
      for (int i = 0; i < size / 2; ++i) std::swap(b[i], b[size - 1 - i]);
    }
    switch (t) {
      case Type::int8:
        return static_cast<double>(static_cast<int8_t>(b[0]));
      case Type::uint8:
        return static_cast<double>(b[0]);
      case Type::int16:
        return load<int16_t>(b);
      case Type::uint16:
        return load<uint16_t>(b);
      case Type::int32:
        return load<int32_t>(b);
      case Type::uint32:
        return load<uint32_t>(b);
      case Type::float32:
        return load<float>(b);
      case Type::float64:
        return load<double>(b);
      case Type::none:
        break;
    }
    return std::nullopt;
  }

  // A value that must be there.
  double required(Type t, const std::string& what) {
    const auto v = value(t);
    if (!v) {
      if (ascii_)
        soup_.fail("has a record with fewer values than its properties declare: " + what + " is missing (" +
                   where() + ")");
      soup_.truncated("the data ends inside " + where());
    }
    return *v;
  }

  // Binary only: can `count` items of `t` still follow?
  bool fits(uint64_t count, Type t) const { return ascii_ || count <= (bytes_.size() - pos_) / type_size(t); }

 private:
  template <typename T>
  static double load(const unsigned char* b) {
    T v;
    std::memcpy(&v, b, sizeof v);
    return static_cast<double>(v);
  }

  std::string_view bytes_;
  size_t pos_;
  bool ascii_, big_;
  LineScanner lines_;
  Tokens tokens_;
  SoupBuilder& soup_;
  const Element* element_ = nullptr;
  uint64_t record_ = 0;
};

std::vector<Element> parse_header(std::string_view bytes, SoupBuilder& soup, std::string& format,
                                  size_t& data) {
  LineScanner lines(bytes);
  std::string_view line, token;
  if (!lines.next(line) || line != "ply") soup.fail("does not parse as ply: it does not start with 'ply'");
  std::vector<Element> elements;
  bool ended = false;
  while (!ended && lines.next(line)) {
    Tokens words(line);
    if (!words.next(token)) continue;
    if (token == "end_header") {
      ended = true;
    } else if (token == "format") {
      words.next(token);
      format = std::string(token);
    } else if (token == "element") {
      Element e;
      std::string_view count;
      if (!words.next(token) || !words.next(count))
        soup.truncated("bad PLY element line (" + lines.where() + ")");
      const auto n = parse_integer(count);
      if (!n || *n < 0)
        soup.truncated("PLY element '" + std::string(token) + "' has a bad count " + quoted(count));
      e.name = std::string(token);
      e.count = static_cast<uint64_t>(*n);
      elements.push_back(std::move(e));
    } else if (token == "property") {
      if (elements.empty()) soup.truncated("a PLY property comes before any element (" + lines.where() + ")");
      Property p;
      std::string_view type, name;
      words.next(type);
      if (type == "list") {
        std::string_view count_type, item_type;
        words.next(count_type);
        words.next(item_type);
        p.count_type = type_from_name(count_type);
        p.type = type_from_name(item_type);
        if (p.count_type == Type::none || p.count_type == Type::float32 || p.count_type == Type::float64)
          soup.truncated("unknown PLY list count type " + quoted(count_type) + " (" + lines.where() + ")");
      } else {
        p.type = type_from_name(type);
      }
      if (p.type == Type::none)
        soup.truncated("unknown PLY property type in " + quoted(line) + " (" + lines.where() + ")");
      words.next(name);
      p.name = std::string(name);
      elements.back().properties.push_back(std::move(p));
    }  // comment, obj_info and unknown header lines are ignored
  }
  if (!ended) soup.fail("does not parse as ply: its header has no end_header");
  data = bytes.size() - lines.bytes_left();
  return elements;
}

}  // namespace

void read_ply(std::string_view bytes, SoupBuilder& soup) {
  std::string format;
  size_t data = 0;
  const std::vector<Element> elements = parse_header(bytes, soup, format, data);
  const bool ascii = format == "ascii";
  if (!ascii && format != "binary_little_endian" && format != "binary_big_endian")
    soup.fail("does not parse as ply: unknown format " + quoted(format));
  RecordReader reader(bytes, data, ascii, format == "binary_big_endian", soup);

  // Caps before any allocation: ascii values take at least 2 bytes, binary records their fixed part.
  uint64_t need = 0;
  for (const auto& e : elements) {
    const uint64_t each =
        ascii ? 2 * std::max<uint64_t>(1, e.properties.size()) : std::max<uint64_t>(1, e.min_record_bytes());
    soup.check_count(e.count, each, reader.bytes_left(), "'" + e.name + "' records");
    need += e.count * each;
  }
  if (need > reader.bytes_left())
    soup.truncated("the PLY header declares more records than its " + std::to_string(bytes.size()) +
                   " bytes can hold");

  uint64_t vertices = 0, triangles = 0;
  for (const auto& e : elements) {
    if (e.name == "vertex") vertices = e.count;
    if (e.name == "face") triangles += e.count;
  }
  soup.reserve(vertices, triangles);

  std::vector<int64_t> list;
  for (const auto& e : elements) {
    const bool is_vertex = e.name == "vertex";
    const bool is_face = e.name == "face", is_strips = e.name == "tristrips";
    int xyz_slot[3] = {-1, -1, -1};
    if (is_vertex) {
      for (size_t i = 0; i < e.properties.size(); ++i) {
        const auto& p = e.properties[i];
        if (p.count_type != Type::none) continue;
        if (p.name == "x") xyz_slot[0] = static_cast<int>(i);
        if (p.name == "y") xyz_slot[1] = static_cast<int>(i);
        if (p.name == "z") xyz_slot[2] = static_cast<int>(i);
      }
      if (e.count > 0 && (xyz_slot[0] < 0 || xyz_slot[1] < 0 || xyz_slot[2] < 0))
        soup.fail("has a PLY vertex element without x, y and z properties");
    }
    for (uint64_t r = 0; r < e.count; ++r) {
      soup.tick();
      reader.begin(e, r);
      double xyz[3] = {0, 0, 0};
      for (size_t i = 0; i < e.properties.size(); ++i) {
        const auto& p = e.properties[i];
        if (p.count_type == Type::none) {
          const double v = reader.required(p.type, "property '" + p.name + "'");
          for (int k = 0; k < 3; ++k)
            if (xyz_slot[k] == static_cast<int>(i)) xyz[k] = v;
          continue;
        }
        const double n = reader.required(p.count_type, "the length of list '" + p.name + "'");
        if (n < 0 || !reader.fits(static_cast<uint64_t>(n), p.type))
          soup.truncated("list '" + p.name + "' of " + reader.where() + " claims " +
                         std::to_string(static_cast<int64_t>(n)) + " items, more than the data holds");
        const bool wanted =
            (is_face || is_strips) && (p.name == "vertex_indices" || p.name == "vertex_index");
        list.clear();
        for (uint64_t k = 0; k < static_cast<uint64_t>(n); ++k) {
          const auto item = reader.value(p.type);
          if (!item) {
            if (is_face)
              soup.fail("has a face claiming " + std::to_string(static_cast<int64_t>(n)) +
                        " vertices but giving " + std::to_string(k) + " (" + reader.where() + ")");
            soup.fail("has a list '" + p.name + "' claiming " + std::to_string(static_cast<int64_t>(n)) +
                      " items but giving " + std::to_string(k) + " (" + reader.where() + ")");
          }
          if (wanted) {
            if (!(*item >= -1.0 && *item <= 2147483647.0) ||
                *item != static_cast<double>(static_cast<int64_t>(*item)))
              soup.fail("has a face vertex index " + std::to_string(*item) + " that is not a valid index (" +
                        reader.where() + ")");
            list.push_back(static_cast<int64_t>(*item));
          }
        }
        if (wanted && is_face) soup.add_polygon(list, reader.where());
        if (wanted && is_strips) soup.add_strip(list, reader.where());
      }
      if (is_vertex) soup.add_vertex(xyz[0], xyz[1], xyz[2], reader.where());
    }
  }
}

}  // namespace depath::io
