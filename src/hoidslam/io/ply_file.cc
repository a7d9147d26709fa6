#include "hoidslam/io/ply_file.h"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "hoidslam/core/error.h"
#include "hoidslam/io/atomic_file.h"
#include "hoidslam/io/files.h"

namespace hoidslam::io {
namespace {

namespace fs = std::filesystem;

static_assert(std::endian::native == std::endian::little, "PLY is written and read as binary_little_endian");
static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float), "vertices are written as they lie in memory");

// ---- The header, shared by every reader ----

enum class PlyFormat { kAscii, kBinaryLittleEndian };

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

struct PlyTypeName {
  std::string_view name;
  PlyType type;
};
// Both spellings PLY files use; the first of each type names it in messages.
constexpr std::array<PlyTypeName, 16> kPlyTypeNames = {{{"char", PlyType::kInt8},
                                                         {"uchar", PlyType::kUint8},
                                                         {"short", PlyType::kInt16},
                                                         {"ushort", PlyType::kUint16},
                                                         {"int", PlyType::kInt32},
                                                         {"uint", PlyType::kUint32},
                                                         {"float", PlyType::kFloat32},
                                                         {"double", PlyType::kFloat64},
                                                         {"int8", PlyType::kInt8},
                                                         {"uint8", PlyType::kUint8},
                                                         {"int16", PlyType::kInt16},
                                                         {"uint16", PlyType::kUint16},
                                                         {"int32", PlyType::kInt32},
                                                         {"uint32", PlyType::kUint32},
                                                         {"float32", PlyType::kFloat32},
                                                         {"float64", PlyType::kFloat64}}};

std::optional<PlyType> TypeNamed(std::string_view name) {
  for (const PlyTypeName& t : kPlyTypeNames) {
    if (t.name == name) return t.type;
  }
  return std::nullopt;
}

std::string_view NameOf(PlyType type) {
  return std::find_if(kPlyTypeNames.begin(), kPlyTypeNames.end(), [&](const auto& t) { return t.type == type; })->name;
}

std::size_t BytesOf(PlyType type) {
  switch (type) {
    case PlyType::kInt8:
    case PlyType::kUint8:
      return 1;
    case PlyType::kInt16:
    case PlyType::kUint16:
      return 2;
    case PlyType::kInt32:
    case PlyType::kUint32:
    case PlyType::kFloat32:
      return 4;
    case PlyType::kFloat64:
      return 8;
  }
  return 8;
}

bool IsInteger(PlyType type) { return type != PlyType::kFloat32 && type != PlyType::kFloat64; }

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat32;    // the value's, or a list's items'
  std::optional<PlyType> list_count;   // a list's count type; nullopt for a single value
};

struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::kAscii;
  std::vector<std::string_view> comments;  // the text after "comment "
  std::vector<PlyElement> elements;        // in file order
  std::size_t body = 0;                    // offset of the first byte after the header
};

const PlyElement* FindElement(const PlyHeader& header, std::string_view name) {
  const auto it = std::find_if(header.elements.begin(), header.elements.end(),
                               [&](const PlyElement& e) { return e.name == name; });
  return it == header.elements.end() ? nullptr : &*it;
}

std::vector<std::string_view> Words(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t at = 0;
  while (true) {
    at = line.find_first_not_of(" \t", at);
    if (at == std::string_view::npos) return words;
    const std::size_t end = std::min(line.find_first_of(" \t", at), line.size());
    words.push_back(line.substr(at, end - at));
    at = end;
  }
}

// Parses the header of any PLY file in ascii or binary_little_endian; throws InputError naming the file and line.
PlyHeader ParsePlyHeader(const fs::path& path, std::string_view text) {
  PlyHeader header;
  std::size_t at = 0;
  std::size_t number = 0;
  const auto next_line = [&] {
    const std::size_t end = text.find('\n', at);
    if (end == std::string_view::npos) throw core::InputError::InFile(path, "the PLY header never ends");
    std::string_view line = text.substr(at, end - at);
    if (line.ends_with('\r')) line.remove_suffix(1);
    at = end + 1;
    ++number;
    return line;
  };
  const auto fail = [&](const std::string& what) { return core::InputError::AtLine(path, number, what); };
  if (next_line() != "ply") throw core::InputError::InFile(path, "not a PLY file: the first line must be 'ply'");
  bool has_format = false;
  while (true) {
    const std::string_view line = next_line();
    const std::vector<std::string_view> words = Words(line);
    const std::string_view keyword = words.empty() ? std::string_view() : words[0];
    if (keyword == "end_header" && words.size() == 1) break;
    if (keyword == "comment") {
      header.comments.push_back(line.substr(std::min(line.size(), line.find(keyword) + keyword.size() + 1)));
    } else if (keyword == "obj_info") {
      continue;
    } else if (keyword == "format") {
      if (has_format || !header.elements.empty()) throw fail("the format line must come once, before the elements");
      if (words.size() != 3 || words[2] != "1.0" || (words[1] != "ascii" && words[1] != "binary_little_endian")) {
        throw fail(fmt::format("'{}': hoidslam reads 'format ascii 1.0' and 'format binary_little_endian 1.0'", line));
      }
      header.format = words[1] == "ascii" ? PlyFormat::kAscii : PlyFormat::kBinaryLittleEndian;
      has_format = true;
    } else if (keyword == "element") {
      std::size_t count = 0;
      const std::string_view digits = words.size() == 3 ? words[2] : std::string_view();
      const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), count);
      if (digits.empty() || error != std::errc() || end != digits.data() + digits.size()) {
        throw fail(fmt::format("'{}' is not 'element <name> <count>'", line));
      }
      header.elements.push_back({std::string(words[1]), count, {}});
    } else if (keyword == "property") {
      if (header.elements.empty()) throw fail("a property before any element");
      PlyProperty property;
      std::optional<PlyType> type;
      if (words.size() == 3) {
        type = TypeNamed(words[1]);
      } else if (words.size() == 5 && words[1] == "list") {
        property.list_count = TypeNamed(words[2]);
        if (!property.list_count || !IsInteger(*property.list_count)) {
          throw fail(fmt::format("'{}': a list's count must be of an integer type", line));
        }
        type = TypeNamed(words[3]);
      } else {
        throw fail(fmt::format("'{}' is not 'property <type> <name>' or 'property list <count type> <type> <name>'",
                               line));
      }
      if (!type) throw fail(fmt::format("'{}': unknown type", line));
      property.type = *type;
      property.name = words.back();
      header.elements.back().properties.push_back(std::move(property));
    } else {
      throw fail(fmt::format("'{}' is not a PLY header line", line));
    }
  }
  if (!has_format) throw fail("end_header before any format line");
  header.body = at;
  return header;
}

// ---- The body, value by value ----

template <typename T>
double Load(const char* bytes) {
  T value;
  std::memcpy(&value, bytes, sizeof(value));
  return static_cast<double>(value);
}

// Reads the values of a PLY body in file order; errors name the file and the record being read.
class PlyValues {
 public:
  PlyValues(const fs::path& path, std::string_view body, PlyFormat format)
      : path_(path), body_(body), format_(format) {}

  // The record that the following values belong to, for messages.
  void At(const PlyElement& element, std::size_t index) {
    element_ = &element;
    index_ = index;
  }

  double Read(PlyType type) { return format_ == PlyFormat::kAscii ? ReadText(type) : ReadBinary(type); }

  // Throws when anything but (in ascii) white space follows the last value.
  void ExpectEnd() {
    if (format_ == PlyFormat::kAscii) SkipSpace();
    if (at_ != body_.size()) {
      throw core::InputError::InFile(
          path_, fmt::format("{} bytes follow the last element the header declares", body_.size() - at_));
    }
  }

  core::InputError Error(const std::string& what) const {
    return core::InputError::InFile(path_, fmt::format("{} {}: {}", element_->name, index_, what));
  }

 private:
  core::InputError EndError() const {
    return Error(fmt::format("the file ends early (the header says 'element {} {}')", element_->name, element_->count));
  }

  double ReadBinary(PlyType type) {
    const std::size_t size = BytesOf(type);
    if (body_.size() - at_ < size) throw EndError();
    const char* bytes = body_.data() + at_;
    at_ += size;
    switch (type) {
      case PlyType::kInt8:
        return Load<std::int8_t>(bytes);
      case PlyType::kUint8:
        return Load<std::uint8_t>(bytes);
      case PlyType::kInt16:
        return Load<std::int16_t>(bytes);
      case PlyType::kUint16:
        return Load<std::uint16_t>(bytes);
      case PlyType::kInt32:
        return Load<std::int32_t>(bytes);
      case PlyType::kUint32:
        return Load<std::uint32_t>(bytes);
      case PlyType::kFloat32:
        return Load<float>(bytes);
      case PlyType::kFloat64:
        return Load<double>(bytes);
    }
    return 0.0;
  }

  static bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

  void SkipSpace() {
    while (at_ < body_.size() && IsSpace(body_[at_])) ++at_;
  }

  double ReadText(PlyType type) {
    SkipSpace();
    if (at_ == body_.size()) throw EndError();
    const char* begin = body_.data() + at_;
    const char* limit = body_.data() + body_.size();
    const char* end = begin;
    bool fits = false;
    double value = 0.0;
    if (IsInteger(type)) {
      long long integer = 0;
      const auto result = std::from_chars(begin, limit, integer);
      end = result.ptr;
      const long long bits = 8 * static_cast<long long>(BytesOf(type));
      const bool is_signed = type == PlyType::kInt8 || type == PlyType::kInt16 || type == PlyType::kInt32;
      fits = result.ec == std::errc() && (is_signed ? integer >= -(1LL << (bits - 1)) && integer < (1LL << (bits - 1))
                                                     : integer >= 0 && integer < (1LL << bits));
      value = static_cast<double>(integer);
    } else {
      const auto result = std::from_chars(begin, limit, value);
      end = result.ptr;
      fits = result.ec == std::errc();
    }
    if (!fits || (end != limit && !IsSpace(*end))) {
      const std::size_t length = std::min(body_.find_first_of(" \t\r\n", at_), body_.size()) - at_;
      throw Error(fmt::format("'{}' is not of type {}", body_.substr(at_, std::min<std::size_t>(length, 40)),
                              NameOf(type)));
    }
    at_ = static_cast<std::size_t>(end - body_.data());
    return value;
  }

  const fs::path& path_;
  std::string_view body_;
  PlyFormat format_;
  std::size_t at_ = 0;
  const PlyElement* element_ = nullptr;
  std::size_t index_ = 0;
};

// What the mesh and voxel readers take from a file: the vertices' x y z and the faces' vertex_indices.
TriangleMesh ReadGeometry(const fs::path& path, std::string_view text, const PlyHeader& header) {
  const PlyElement* vertex = FindElement(header, "vertex");
  const PlyElement* face = FindElement(header, "face");
  if (vertex == nullptr) throw core::InputError::InFile(path, "no vertex element in the PLY header");
  for (const PlyElement& element : header.elements) {
    if (&element != vertex && &element != face && (element.name == "vertex" || element.name == "face")) {
      throw core::InputError::InFile(path, fmt::format("two {} elements in the PLY header", element.name));
    }
  }
  // Where x, y, z and vertex_indices sit among their element's properties.
  std::array<std::size_t, 3> xyz{};
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const std::string_view name = std::array{"x", "y", "z"}[axis];
    const auto it = std::find_if(vertex->properties.begin(), vertex->properties.end(),
                                 [&](const PlyProperty& p) { return p.name == name; });
    if (it == vertex->properties.end() || it->list_count || IsInteger(it->type)) {
      throw core::InputError::InFile(path, fmt::format("the vertices have no float or double property {}", name));
    }
    xyz[axis] = static_cast<std::size_t>(it - vertex->properties.begin());
  }
  // Where red, green and blue sit, when all three are there as uchar (Open3D's and WritePlyMesh's colours).
  std::array<std::size_t, 3> rgb{};
  bool has_rgb = true;
  for (std::size_t channel = 0; channel < 3; ++channel) {
    const std::string_view name = std::array{"red", "green", "blue"}[channel];
    const auto it = std::find_if(vertex->properties.begin(), vertex->properties.end(), [&](const PlyProperty& p) {
      return p.name == name && !p.list_count && p.type == PlyType::kUint8;
    });
    has_rgb = has_rgb && it != vertex->properties.end();
    rgb[channel] = static_cast<std::size_t>(it - vertex->properties.begin());
  }
  std::size_t indices = 0;
  if (face != nullptr) {
    const auto it = std::find_if(face->properties.begin(), face->properties.end(),
                                 [](const PlyProperty& p) { return p.name == "vertex_indices"; });
    if (it == face->properties.end() || !it->list_count || !IsInteger(it->type)) {
      throw core::InputError::InFile(path, "the faces have no list of integers vertex_indices");
    }
    indices = static_cast<std::size_t>(it - face->properties.begin());
  }
  if (vertex->count > static_cast<std::size_t>(INT_MAX)) {
    throw core::InputError::InFile(path, fmt::format("{} vertices: more than an int index reaches", vertex->count));
  }

  const std::string_view body = text.substr(header.body);
  TriangleMesh mesh;
  if (header.format == PlyFormat::kBinaryLittleEndian) {
    // Counts beyond what the file can hold are refused before anything is allocated for them.
    std::size_t left = body.size();
    for (const PlyElement& element : header.elements) {
      std::size_t record = 0;
      for (const PlyProperty& p : element.properties) record += BytesOf(p.list_count ? *p.list_count : p.type);
      if (record > 0 && element.count > left / record) {
        throw core::InputError::InFile(
            path, fmt::format("'element {} {}' needs {} bytes or more per {}, more than the {} bytes after the "
                              "header hold",
                              element.name, element.count, record, element.name, body.size()));
      }
      left -= element.count * record;
    }
    mesh.vertices.reserve(vertex->count);
    if (has_rgb) mesh.rgb.reserve(vertex->count);
    if (face != nullptr) mesh.triangles.reserve(face->count);
  }
  PlyValues values(path, body, header.format);
  for (const PlyElement& element : header.elements) {
    if (element.properties.empty()) continue;  // nothing to read, however many
    for (std::size_t i = 0; i < element.count; ++i) {
      values.At(element, i);
      Eigen::Vector3f position = Eigen::Vector3f::Zero();
      cv::Vec3b colour;
      for (std::size_t p = 0; p < element.properties.size(); ++p) {
        const PlyProperty& property = element.properties[p];
        if (!property.list_count) {
          const double value = values.Read(property.type);
          if (&element != vertex) continue;
          for (std::size_t axis = 0; axis < 3; ++axis) {
            if (p == xyz[axis]) position[static_cast<Eigen::Index>(axis)] = static_cast<float>(value);
            if (p == rgb[axis]) colour[static_cast<int>(axis)] = static_cast<std::uint8_t>(value);
          }
          continue;
        }
        const double items = values.Read(*property.list_count);
        if (items < 0) throw values.Error(fmt::format("a list of {} items", items));
        if (&element != face || p != indices) {
          for (double item = 0; item < items; ++item) values.Read(property.type);
          continue;
        }
        if (items != 3) throw values.Error(fmt::format("{} vertices: hoidslam reads triangle meshes only", items));
        Eigen::Vector3i triangle;
        for (int corner = 0; corner < 3; ++corner) {
          const double index = values.Read(property.type);
          if (index < 0 || index >= static_cast<double>(vertex->count)) {
            throw values.Error(fmt::format("vertex index {} is out of range ({} vertices)", index, vertex->count));
          }
          triangle[corner] = static_cast<int>(index);
        }
        mesh.triangles.push_back(triangle);
      }
      if (&element == vertex) {
        mesh.vertices.push_back(position);
        if (has_rgb) mesh.rgb.push_back(colour);
      }
    }
  }
  values.ExpectEnd();
  return mesh;
}

std::string_view AsText(const std::vector<std::uint8_t>& bytes) {
  return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

// ---- Writing ----

constexpr std::string_view kBinaryPly = "ply\nformat binary_little_endian 1.0\n";
constexpr std::string_view kXyzProperties = "property float x\nproperty float y\nproperty float z\n";

// ReadPly's layout: float x y z, uchar red green blue.
constexpr std::size_t kColoredRecordBytes = 15;
constexpr std::string_view kColorProperties = "property uchar red\nproperty uchar green\nproperty uchar blue\n";

// One vertex in that layout.
void WriteColoredVertex(std::ostream& out, const Eigen::Vector3f& position, const cv::Vec3b& rgb) {
  std::array<char, kColoredRecordBytes> record{};
  std::memcpy(record.data(), position.data(), sizeof(Eigen::Vector3f));
  std::memcpy(record.data() + sizeof(Eigen::Vector3f), rgb.val, 3);
  out.write(record.data(), record.size());
}

void WriteXyz(std::ostream& out, std::span<const Eigen::Vector3f> points) {
  out.write(reinterpret_cast<const char*>(points.data()),
            static_cast<std::streamsize>(points.size() * sizeof(Eigen::Vector3f)));
}

}  // namespace

void WritePly(const fs::path& path, std::span<const ColoredPoint> points) {
  AtomicFile file(path);
  std::ostream& out = file.stream();
  out << kBinaryPly << "comment hoidslam sparse map\n"
      << "element vertex " << points.size() << "\n"
      << kXyzProperties << kColorProperties << "end_header\n";
  for (const ColoredPoint& p : points) {
    WriteColoredVertex(out, p.position.cast<float>(), cv::Vec3b(p.bgr[2], p.bgr[1], p.bgr[0]));
  }
  file.Commit();
}

std::vector<ColoredPoint> ReadPly(const fs::path& path) {
  const std::vector<std::uint8_t> bytes = ReadBinaryFile(path, "point cloud");
  const std::string_view text = AsText(bytes);
  const PlyHeader header = ParsePlyHeader(path, text);
  // Only the layout WritePly writes.
  const auto is = [](const PlyProperty& property, PlyType type, std::string_view name) {
    return !property.list_count && property.type == type && property.name == name;
  };
  const std::vector<PlyProperty>* properties =
      header.elements.size() == 1 && header.elements[0].name == "vertex" ? &header.elements[0].properties : nullptr;
  if (header.format != PlyFormat::kBinaryLittleEndian || properties == nullptr || properties->size() != 6 ||
      !is((*properties)[0], PlyType::kFloat32, "x") || !is((*properties)[1], PlyType::kFloat32, "y") ||
      !is((*properties)[2], PlyType::kFloat32, "z") || !is((*properties)[3], PlyType::kUint8, "red") ||
      !is((*properties)[4], PlyType::kUint8, "green") || !is((*properties)[5], PlyType::kUint8, "blue")) {
    throw core::InputError::InFile(path, "not a point cloud as hoidslam writes it (binary_little_endian, float x y z, "
                                         "uchar red green blue)");
  }
  const std::size_t count = header.elements[0].count;
  std::size_t at = header.body;
  const std::size_t body = text.size() - at;
  if (body % kColoredRecordBytes != 0 || body / kColoredRecordBytes != count) {
    throw core::InputError::InFile(
        path, fmt::format("the header says {} points, the {} bytes after it hold {:.4g}", count, body,
                          static_cast<double>(body) / kColoredRecordBytes));
  }
  std::vector<ColoredPoint> points(count);
  for (ColoredPoint& point : points) {
    float xyz[3];
    std::memcpy(xyz, text.data() + at, sizeof(xyz));
    const auto* rgb = reinterpret_cast<const unsigned char*>(text.data() + at + sizeof(xyz));
    point.position = Eigen::Vector3f(xyz[0], xyz[1], xyz[2]).cast<double>();
    point.bgr = cv::Vec3b(rgb[2], rgb[1], rgb[0]);
    at += kColoredRecordBytes;
  }
  return points;
}

void WritePlyMesh(const fs::path& path, const TriangleMesh& mesh, std::string_view comment) {
  const bool coloured = !mesh.rgb.empty();
  if (coloured && mesh.rgb.size() != mesh.vertices.size()) {
    throw std::invalid_argument(fmt::format("WritePlyMesh: {} colours for {} vertices", mesh.rgb.size(),
                                            mesh.vertices.size()));
  }
  std::string one_line(comment);
  std::replace_if(one_line.begin(), one_line.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  AtomicFile file(path);
  std::ostream& out = file.stream();
  out << kBinaryPly << "comment " << one_line << "\n"
      << "element vertex " << mesh.vertices.size() << "\n"
      << kXyzProperties << (coloured ? kColorProperties : "") << "element face " << mesh.triangles.size() << "\n"
      << "property list uchar int vertex_indices\nend_header\n";
  if (coloured) {
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) WriteColoredVertex(out, mesh.vertices[i], mesh.rgb[i]);
  } else {
    WriteXyz(out, mesh.vertices);
  }
  for (const Eigen::Vector3i& triangle : mesh.triangles) {
    std::array<char, 1 + 3 * sizeof(std::int32_t)> record{};
    record[0] = 3;
    std::memcpy(record.data() + 1, triangle.data(), 3 * sizeof(std::int32_t));
    out.write(record.data(), record.size());
  }
  file.Commit();
}

TriangleMesh ReadPlyMesh(const fs::path& path) {
  const std::vector<std::uint8_t> bytes = ReadBinaryFile(path, "mesh");
  const std::string_view text = AsText(bytes);
  return ReadGeometry(path, text, ParsePlyHeader(path, text));
}

void WriteVoxelCentresPly(const fs::path& path, const VoxelCentres& voxels) {
  AtomicFile file(path);
  std::ostream& out = file.stream();
  out << kBinaryPly << fmt::format("comment voxel_size {}\n", voxels.voxel_size)
      << "element vertex " << voxels.centres.size() << "\n"
      << kXyzProperties << "end_header\n";
  WriteXyz(out, voxels.centres);
  file.Commit();
}

VoxelCentres ReadVoxelCentresPly(const fs::path& path) {
  const std::vector<std::uint8_t> bytes = ReadBinaryFile(path, "voxel centres");
  const std::string_view text = AsText(bytes);
  const PlyHeader header = ParsePlyHeader(path, text);
  constexpr std::string_view kKey = "voxel_size ";
  std::optional<double> size;
  for (const std::string_view comment : header.comments) {
    if (!comment.starts_with(kKey)) continue;
    const std::string_view number = comment.substr(kKey.size());
    double value = 0.0;
    const auto [end, error] = std::from_chars(number.data(), number.data() + number.size(), value);
    if (size || error != std::errc() || end != number.data() + number.size() || !std::isfinite(value) ||
        value <= 0.0) {
      throw core::InputError::InFile(
          path, fmt::format("'comment {}': the header must say the voxel size once, in metres > 0", comment));
    }
    size = value;
  }
  if (!size) throw core::InputError::InFile(path, "no 'comment voxel_size <metres>' line in the PLY header");
  if (FindElement(header, "face") != nullptr) {
    throw core::InputError::InFile(path, "a face element: voxel centres are vertices only");
  }
  return {*size, ReadGeometry(path, text, header).vertices};
}

std::uint64_t PackCell(std::int64_t i, std::int64_t j, std::int64_t k) {
  return static_cast<std::uint64_t>(i + kCellReach) << (2 * kCellBits) |
         static_cast<std::uint64_t>(j + kCellReach) << kCellBits | static_cast<std::uint64_t>(k + kCellReach);
}

std::int64_t UnpackCell(std::uint64_t key, int axis) {
  constexpr std::uint64_t kMask = (std::uint64_t{1} << kCellBits) - 1;
  return static_cast<std::int64_t>((key >> ((2 - axis) * kCellBits)) & kMask) - kCellReach;
}

std::uint64_t CellKeyOf(const Eigen::Vector3d& point, double size) {
  const auto index = [&](int axis) { return static_cast<std::int64_t>(std::floor(point[axis] / size)); };
  return PackCell(index(0), index(1), index(2));
}

}  // namespace hoidslam::io
