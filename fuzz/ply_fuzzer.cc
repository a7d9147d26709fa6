// Point clouds: the bytes are a map.ply as the report reads it (io::ReadPly).

#include <cmath>
#include <stdexcept>

#include "fuzz/targets.h"
#include "hoidslam/io/ply_file.h"

namespace hoidslam::fuzz {

void FuzzPly(Bytes input) {
  const std::filesystem::path path = ScratchDir() / "map.ply";
  WriteBytes(path, input);
  const auto points = ParseOrReject([&] { return io::ReadPly(path); }, path.string());
  if (!points) return;
  // What was read writes back as the same points: the reader takes what the writer writes, and nothing else.
  const std::filesystem::path again = ScratchDir() / "again.ply";
  io::WritePly(again, *points);
  const std::vector<io::ColoredPoint> reread = io::ReadPly(again);
  if (reread.size() != points->size()) throw std::logic_error("a PLY read and written again lost points");
  const auto same = [](double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); };
  for (std::size_t i = 0; i < reread.size(); ++i) {
    const Eigen::Vector3d& a = (*points)[i].position;
    const Eigen::Vector3d& b = reread[i].position;
    if (reread[i].bgr != (*points)[i].bgr || !same(a.x(), b.x()) || !same(a.y(), b.y()) || !same(a.z(), b.z())) {
      throw std::logic_error("a PLY read and written again changed a point");
    }
  }
}

}  // namespace hoidslam::fuzz
