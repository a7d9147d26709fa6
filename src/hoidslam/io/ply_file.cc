#include "hoidslam/io/ply_file.h"

#include <array>
#include <bit>
#include <cstring>

#include "hoidslam/io/atomic_file.h"

namespace hoidslam::io {

void WritePly(const std::filesystem::path& path, std::span<const ColoredPoint> points) {
  static_assert(std::endian::native == std::endian::little, "PLY is written as binary_little_endian");
  AtomicFile file(path);
  std::ostream& out = file.stream();
  out << "ply\nformat binary_little_endian 1.0\ncomment hoidslam sparse map\n"
      << "element vertex " << points.size() << "\n"
      << "property float x\nproperty float y\nproperty float z\n"
      << "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  for (const ColoredPoint& p : points) {
    std::array<char, 15> record{};
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

}  // namespace hoidslam::io
