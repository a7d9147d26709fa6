#include "hoidslam/io/ply_file.h"

#include <array>
#include <bit>
#include <charconv>
#include <cstring>
#include <string_view>

#include <fmt/format.h>

#include "hoidslam/core/error.h"
#include "hoidslam/io/atomic_file.h"
#include "hoidslam/io/files.h"

namespace hoidslam::io {
namespace {

constexpr std::size_t kRecordBytes = 15;  // float x, y, z; uchar red, green, blue
constexpr std::string_view kProperties =
    "property float x\nproperty float y\nproperty float z\n"
    "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";

}  // namespace

void WritePly(const std::filesystem::path& path, std::span<const ColoredPoint> points) {
  static_assert(std::endian::native == std::endian::little, "PLY is written as binary_little_endian");
  AtomicFile file(path);
  std::ostream& out = file.stream();
  out << "ply\nformat binary_little_endian 1.0\ncomment hoidslam sparse map\n"
      << "element vertex " << points.size() << "\n"
      << kProperties;
  for (const ColoredPoint& p : points) {
    std::array<char, kRecordBytes> record{};
    const float xyz[3] = {static_cast<float>(p.position.x()), static_cast<float>(p.position.y()),
                          static_cast<float>(p.position.z())};
    std::memcpy(record.data(), xyz, sizeof(xyz));
    record[12] = static_cast<char>(p.bgr[2]);
    record[13] = static_cast<char>(p.bgr[1]);
    record[14] = static_cast<char>(p.bgr[0]);
    out.write(record.data(), record.size());
  }
  file.Commit();
}

std::vector<ColoredPoint> ReadPly(const std::filesystem::path& path) {
  const std::vector<std::uint8_t> bytes = ReadBinaryFile(path, "point cloud");
  const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  // The header as WritePly writes it, comment lines aside.
  std::size_t at = 0;
  const auto line = [&] {
    const std::size_t end = text.find('\n', at);
    if (end == std::string_view::npos) throw core::InputError::InFile(path, "the PLY header never ends");
    const std::string_view read = text.substr(at, end - at);
    at = end + 1;
    return read;
  };
  const auto layout_error = [&] {
    return core::InputError::InFile(path, "not a point cloud as hoidslam writes it (binary_little_endian, float x y z, "
                                          "uchar red green blue)");
  };
  if (line() != "ply" || line() != "format binary_little_endian 1.0") throw layout_error();
  std::string_view element = line();
  while (element.starts_with("comment ")) element = line();
  constexpr std::string_view kElement = "element vertex ";
  if (!element.starts_with(kElement)) throw layout_error();
  const std::string_view digits = element.substr(kElement.size());
  std::size_t count = 0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), count);
  if (error != std::errc() || end != digits.data() + digits.size()) throw layout_error();
  if (text.substr(at, kProperties.size()) != kProperties) throw layout_error();
  at += kProperties.size();
  const std::size_t body = text.size() - at;
  if (body % kRecordBytes != 0 || body / kRecordBytes != count) {
    throw core::InputError::InFile(
        path, fmt::format("the header says {} points, the {} bytes after it hold {:.4g}", count, body,
                          static_cast<double>(body) / kRecordBytes));
  }
  std::vector<ColoredPoint> points(count);
  for (ColoredPoint& point : points) {
    float xyz[3];
    std::memcpy(xyz, text.data() + at, sizeof(xyz));
    const auto* rgb = reinterpret_cast<const unsigned char*>(text.data() + at + sizeof(xyz));
    point.position = Eigen::Vector3f(xyz[0], xyz[1], xyz[2]).cast<double>();
    point.bgr = cv::Vec3b(rgb[2], rgb[1], rgb[0]);
    at += kRecordBytes;
  }
  return points;
}

}  // namespace hoidslam::io
