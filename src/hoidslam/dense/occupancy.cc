#include "hoidslam/dense/occupancy.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <limits>
#include <stdexcept>
#include <string>

#include <fmt/format.h>
#include <octomap/OcTree.h>
#include <opencv2/core.hpp>

#include "hoidslam/core/error.h"
#include "hoidslam/io/atomic_file.h"

namespace hoidslam::dense {

struct OccupancyMap::Impl {
  explicit Impl(const OccupancyOptions& o) : options(o), tree(o.resolution) {}

  OccupancyOptions options;
  // Updated lazily (InsertDepth): its leaves hold the map, its inner nodes are not kept up to date and nothing here
  // reads them.
  octomap::OcTree tree;
};

namespace {

// Calls visit(centre, occupied) for every leaf of the finest resolution the tree knows. OctoMap merges eight
// children that agree into their parent (pruning, after every update), so a leaf may be a cube of many cells:
// it is expanded here, so that each cell counts once and projects from its own centre.
template <typename Visit>
void ForEachFinestLeaf(const octomap::OcTree& tree, Visit visit) {
  const unsigned tree_depth = tree.getTreeDepth();
  for (auto leaf = tree.begin_leafs(), end = tree.end_leafs(); leaf != end; ++leaf) {
    const bool occupied = tree.isNodeOccupied(*leaf);
    const int cells = 1 << (tree_depth - leaf.getDepth());
    const octomap::OcTreeKey corner = leaf.getIndexKey();  // the key of the cube's lowest cell
    for (int i = 0; i < cells; ++i) {
      for (int j = 0; j < cells; ++j) {
        for (int k = 0; k < cells; ++k) {
          const octomap::OcTreeKey key(corner[0] + i, corner[1] + j, corner[2] + k);
          const octomap::point3d centre = tree.keyToCoord(key);
          visit(Eigen::Vector3d(centre.x(), centre.y(), centre.z()), occupied);
        }
      }
    }
  }
}

// ROS map_server's trinary reading of a pixel v is p = (255 - v) / 255: occupied above occupied_thresh (0.65), free
// below free_thresh (0.196), unknown between.
std::uint8_t PgmValue(std::int8_t cell) {
  if (cell == OccupancyGrid::kOccupied) return 0;
  if (cell == OccupancyGrid::kFree) return 254;
  return 205;
}

}  // namespace

OccupancyMap::OccupancyMap(const OccupancyOptions& options) {
  options.Check();
  impl_ = std::make_unique<Impl>(options);
}

OccupancyMap::~OccupancyMap() = default;

void OccupancyMap::InsertDepth(const cv::Mat& depth, const core::CameraIntrinsics& camera, const core::Pose& T_wc,
                               double max_depth) {
  if (depth.type() != CV_32FC1) {
    throw std::invalid_argument("OccupancyMap::InsertDepth: depth image must be CV_32FC1 (metres)");
  }
  const int step = impl_->options.pixel_step;
  octomap::Pointcloud ends;      // rays that end on a surface
  octomap::Pointcloud far_ends;  // rays cut at max_depth: free space, no surface
  ends.reserve(static_cast<std::size_t>(((depth.rows + step - 1) / step) * ((depth.cols + step - 1) / step)));
  const auto push = [&T_wc](octomap::Pointcloud& cloud, const Eigen::Vector3d& p_c) {
    const Eigen::Vector3d p_w = T_wc * p_c;
    cloud.push_back(static_cast<float>(p_w.x()), static_cast<float>(p_w.y()), static_cast<float>(p_w.z()));
  };
  for (int v = 0; v < depth.rows; v += step) {
    const float* row = depth.ptr<float>(v);
    for (int u = 0; u < depth.cols; u += step) {
      const float z = row[u];
      if (!(z > 0.0F) || !std::isfinite(z)) continue;  // 0, NaN or infinite: no ray
      if (z > max_depth) {
        // Every other one in x and y: a cut ray crosses max_depth / resolution cells, an ending one fewer, and
        // at 3 m rays 2 × 4 pixels apart are still under a 5 cm cell apart.
        if ((u / step) % 2 == 0 && (v / step) % 2 == 0) push(far_ends, camera.Unproject(u, v, max_depth));
      } else {
        push(ends, camera.Unproject(u, v, z));
      }
    }
  }
  const Eigen::Vector3d origin = T_wc.translation();
  const octomap::point3d sensor(static_cast<float>(origin.x()), static_cast<float>(origin.y()),
                                static_cast<float>(origin.z()));
  // One scan, as OctoMap's insertPointCloud with discretize makes it (the rays that end in the same cell cast once: a
  // quarter faster on a TUM keyframe at 5 cm), and a cell that one ray ends in and another crosses is occupied. The
  // cut rays only free: where they stop there is no surface.
  octomap::OcTree& tree = impl_->tree;
  octomap::KeySet free_cells, occupied_cells, far_free, far_stops;
  tree.computeDiscreteUpdate(ends, sensor, free_cells, occupied_cells, /*maxrange=*/-1.0);
  if (far_ends.size() > 0) {
    tree.computeDiscreteUpdate(far_ends, sensor, far_free, far_stops, /*maxrange=*/-1.0);
    free_cells.insert(far_free.begin(), far_free.end());
  }
  // Lazily: OctoMap would otherwise bring every inner node on the way to a cell up to date after each update and
  // prune what then agrees, to expand it again at the next view's update; in a room's tree the rays took twice as
  // long as the volume's integration (51 against 26 ms a keyframe on `loop`'s first 3,600 frames, 27 lazily). The
  // leaves' values are the same either way, and the tree, unpruned, grows with the space seen rather than with the
  // views (20 MB more there; WriteBinary prunes its copy).
  for (const octomap::OcTreeKey& key : free_cells) {
    if (occupied_cells.find(key) == occupied_cells.end()) tree.updateNode(key, false, /*lazy_eval=*/true);
  }
  for (const octomap::OcTreeKey& key : occupied_cells) tree.updateNode(key, true, /*lazy_eval=*/true);
}

std::vector<Eigen::Vector3d> OccupancyMap::OccupiedCentres() const {
  std::vector<Eigen::Vector3d> centres;
  ForEachFinestLeaf(impl_->tree, [&](const Eigen::Vector3d& centre, bool occupied) {
    if (occupied) centres.push_back(centre);
  });
  return centres;
}

OccupiedCells ReadOccupiedCells(const std::filesystem::path& path) {
  // The header read here, the nodes by OctoMap: its own readBinary says "Reading binary octree type OcTree" on stderr.
  std::ifstream in(path, std::ios::binary);
  std::string line;
  if (!std::getline(in, line) || line != "# Octomap OcTree binary file") {
    throw core::InputError::InFile(path, "not an OctoMap binary tree (.bt): its first line is not OctoMap's");
  }
  std::string id;
  double resolution = 0.0;
  while (std::getline(in, line) && line != "data") {
    std::istringstream fields(line);
    std::string key;
    fields >> key;
    if (key == "id") fields >> id;
    if (key == "res") fields >> resolution;
  }
  if (line != "data" || id != "OcTree" || !(resolution > 0.0)) {
    throw core::InputError::InFile(path, "an OctoMap binary tree needs 'id OcTree', 'res <m>' and 'data' in its header");
  }
  octomap::OcTree tree(resolution);
  if (!tree.readBinaryData(in)) throw core::InputError::InFile(path, "its tree ends early or is damaged");
  OccupiedCells cells{resolution, {}};
  ForEachFinestLeaf(tree, [&](const Eigen::Vector3d& centre, bool occupied) {
    if (occupied) cells.centres.push_back(centre);
  });
  return cells;
}

std::size_t OccupancyMap::OccupiedLeaves() const {
  std::size_t count = 0;
  ForEachFinestLeaf(impl_->tree, [&](const Eigen::Vector3d&, bool occupied) { count += occupied ? 1 : 0; });
  return count;
}

CellState OccupancyMap::At(const Eigen::Vector3d& p_w) const {
  const octomap::OcTreeNode* node = impl_->tree.search(p_w.x(), p_w.y(), p_w.z());
  if (node == nullptr) return CellState::kUnknown;
  return impl_->tree.isNodeOccupied(node) ? CellState::kOccupied : CellState::kFree;
}

void OccupancyMap::WriteBinary(const std::filesystem::path& path) const {
  io::AtomicFile file(path);
  // writeBinary turns the log-odds into maximum likelihood and prunes what then agrees, the smaller file: on a copy,
  // so that this map keeps its log-odds for more keyframes.
  octomap::OcTree copy(impl_->tree);
  copy.toMaxLikelihood();
  copy.prune();
  // OctoMap's own writeBinary would do the same, but Debian's build prints "Writing N nodes to output stream..."
  // on stderr while it does: its header, then its nodes, written here.
  std::ostream& out = file.stream();
  out << "# Octomap OcTree binary file"  // the first line readBinary checks (AbstractOccupancyOcTree::binaryFileHeader)
      << "\n# (feel free to add / change comments, but leave the first line as it is!)\n#\n"
      << "id " << copy.getTreeType() << "\nsize " << copy.size() << "\nres " << copy.getResolution() << "\ndata\n";
  if (copy.getRoot() != nullptr) copy.writeBinaryNode(out, copy.getRoot());
  if (!out) throw core::InputError::InFile(path, "cannot write the occupancy tree");
  file.Commit();
}

OccupancyGrid OccupancyMap::Project(const core::Pose& T_fw) const {
  const OccupancyOptions& options = impl_->options;
  struct Column {
    Eigen::Vector2i index;
    std::int8_t value;
  };
  std::vector<Column> columns;
  Eigen::Vector2i low = Eigen::Vector2i::Constant(std::numeric_limits<int>::max());
  Eigen::Vector2i high = Eigen::Vector2i::Constant(std::numeric_limits<int>::min());
  ForEachFinestLeaf(impl_->tree, [&](const Eigen::Vector3d& centre_w, bool occupied) {
    const Eigen::Vector3d p = T_fw * centre_w;
    if (p.z() < options.band_low || p.z() > options.band_high) return;
    const Eigen::Vector2i index(static_cast<int>(std::floor(p.x() / options.resolution)),
                                static_cast<int>(std::floor(p.y() / options.resolution)));
    columns.push_back({index, occupied ? OccupancyGrid::kOccupied : OccupancyGrid::kFree});
    low = low.cwiseMin(index);
    high = high.cwiseMax(index);
  });

  OccupancyGrid grid;
  grid.resolution = options.resolution;
  grid.T_fw = T_fw;
  if (columns.empty()) return grid;
  grid.origin = low.cast<double>() * options.resolution;
  grid.width = high.x() - low.x() + 1;
  grid.height = high.y() - low.y() + 1;
  grid.cells.assign(static_cast<std::size_t>(grid.width) * static_cast<std::size_t>(grid.height),
                    OccupancyGrid::kUnknown);
  for (const Column& column : columns) {
    const Eigen::Vector2i cell = column.index - low;
    std::int8_t& value = grid.cells[static_cast<std::size_t>(cell.y()) * static_cast<std::size_t>(grid.width) +
                                    static_cast<std::size_t>(cell.x())];
    value = std::max(value, column.value);  // occupied (100) wins over free (0), free over unknown (-1)
  }
  return grid;
}

void WriteOccupancyGrid(const OccupancyGrid& grid, const std::filesystem::path& pgm,
                        const std::filesystem::path& yaml) {
  if (grid.cells.empty()) {
    throw core::InputError::InFile(
        pgm, "the occupancy grid is empty: no depth fell in the height band (--occupancy-band)");
  }
  if (grid.width <= 0 || grid.height <= 0 ||
      grid.cells.size() != static_cast<std::size_t>(grid.width) * static_cast<std::size_t>(grid.height)) {
    throw std::invalid_argument("WriteOccupancyGrid: the grid needs width × height cells");
  }
  cv::Mat image(grid.height, grid.width, CV_8UC1);
  for (int row = 0; row < grid.height; ++row) {
    const std::int8_t* cells = grid.cells.data() + static_cast<std::size_t>(row) * static_cast<std::size_t>(grid.width);
    auto* pixels = image.ptr<std::uint8_t>(grid.height - 1 - row);  // images run top-down, the grid's y up
    for (int column = 0; column < grid.width; ++column) pixels[column] = PgmValue(cells[column]);
  }

  // map_server reads the image relative to the YAML's folder.
  const std::filesystem::path image_name = std::filesystem::absolute(pgm).lexically_normal().lexically_relative(
      std::filesystem::absolute(yaml).parent_path().lexically_normal());
  const Eigen::Matrix4d T = grid.T_fw.matrix();
  // The YAML names the image: opened first and committed last, so that it never points at a missing image.
  io::AtomicFile description(yaml);
  // The origin to nine digits: 0.15 rather than 0.15000000000000002.
  description.stream() << fmt::format(
      "image: {}\nresolution: {}\norigin: [{:.9g}, {:.9g}, 0.0]\nnegate: 0\noccupied_thresh: 0.65\n"
      "free_thresh: 0.196\nmode: trinary\n",
      image_name.string(), grid.resolution, grid.origin.x(), grid.origin.y());
  description.stream() << fmt::format(
      "# floor_from_world (hoidslam's; map_server ignores it): the rigid transform, row by row, from the SLAM world\n"
      "# frame (the trajectory, occupancy.bt) to this map's (z up, the floor at z = 0): world point p is at\n"
      "# floor_from_world * [p, 1] on the map.\n"
      "floor_from_world: [[{}, {}, {}, {}], [{}, {}, {}, {}], [{}, {}, {}, {}], [0, 0, 0, 1]]\n",
      T(0, 0), T(0, 1), T(0, 2), T(0, 3), T(1, 0), T(1, 1), T(1, 2), T(1, 3), T(2, 0), T(2, 1), T(2, 2), T(2, 3));
  io::WriteImageAtomically(pgm, image);
  description.Commit();
}

}  // namespace hoidslam::dense
