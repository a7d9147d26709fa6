#include "hoidslam/eval/dense_score.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <unordered_set>

#include <open3d/core/Tensor.h>
#include <open3d/t/geometry/RaycastingScene.h>

#include "hoidslam/core/error.h"
#include "hoidslam/eval/ate.h"

namespace hoidslam::eval {

namespace {

namespace o3c = open3d::core;

// A frame's pose is its ground truth's within this, seconds (a synthetic sequence has one at every frame).
constexpr double kPoseTolerance = 0.01;
// m², a triangle with less is a line or a point.
constexpr double kNoArea = 1e-12;
// Queries go in batches so that the tensors stay small.
constexpr std::size_t kBatch = 1 << 18;
// A surface sample counts as seen when the depth the view measured at its pixel is this close to its own (or three
// of the sensor's standard deviations there, when more): farther means something stood in front of it.
constexpr double kVisibilityTolerance = 0.02;

o3c::Tensor PointsTensor(const std::vector<Eigen::Vector3f>& points) {
  o3c::Tensor tensor({static_cast<std::int64_t>(points.size()), 3}, o3c::Float32);
  float* data = tensor.GetDataPtr<float>();
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (int k = 0; k < 3; ++k) data[3 * i + k] = points[i][k];
  }
  return tensor;
}

double TriangleArea(const std::vector<Eigen::Vector3f>& v, const Eigen::Vector3i& t) {
  return 0.5 * static_cast<double>((v[t[1]] - v[t[0]]).cross(v[t[2]] - v[t[0]]).norm());
}

// A scene of `mesh` for distance queries (Embree, through Open3D).
class Surface {
 public:
  explicit Surface(const io::TriangleMesh& mesh) {
    // Without triangles of no area (marching cubes makes some): Open3D's closest-point query trips its own
    // assertion on them.
    std::vector<Eigen::Vector3i> kept;
    for (const Eigen::Vector3i& t : mesh.triangles) {
      if (TriangleArea(mesh.vertices, t) > kNoArea) kept.push_back(t);
    }
    o3c::Tensor triangles({static_cast<std::int64_t>(kept.size()), 3}, o3c::UInt32);
    std::uint32_t* t = triangles.GetDataPtr<std::uint32_t>();
    for (std::size_t i = 0; i < kept.size(); ++i) {
      for (int k = 0; k < 3; ++k) t[3 * i + k] = static_cast<std::uint32_t>(kept[i][k]);
    }
    if (!kept.empty()) scene_.AddTriangles(PointsTensor(mesh.vertices), triangles);
    empty_ = kept.empty();
  }

  // Each point's distance to the surface (infinity when it has none).
  std::vector<float> Distances(const std::vector<Eigen::Vector3f>& points) {
    std::vector<float> distances(points.size(), std::numeric_limits<float>::infinity());
    if (empty_) return distances;
    for (std::size_t begin = 0; begin < points.size(); begin += kBatch) {
      const std::size_t end = std::min(points.size(), begin + kBatch);
      const std::vector<Eigen::Vector3f> batch(points.begin() + begin, points.begin() + end);
      const o3c::Tensor d = scene_.ComputeDistance(PointsTensor(batch));
      std::copy_n(d.GetDataPtr<float>(), end - begin, distances.begin() + begin);
    }
    return distances;
  }

 private:
  open3d::t::geometry::RaycastingScene scene_;
  bool empty_ = true;
};

double Percentile(std::vector<float> values, double share) {
  if (values.empty()) return 0.0;
  const auto at = values.begin() + static_cast<std::ptrdiff_t>(share * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), at, values.end());
  return *at;
}

// Points spread over the mesh's triangles, about one per spacing², with their triangle's outward normal; the same on
// every call (a fixed seed).
struct SurfaceSamples {
  std::vector<Eigen::Vector3f> points, normals;
};
SurfaceSamples SampleSurface(const io::TriangleMesh& mesh, double spacing) {
  SurfaceSamples samples;
  std::mt19937 random(0);
  std::uniform_real_distribution<float> unit(0.0F, 1.0F);
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3f a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
    const Eigen::Vector3f normal = (b - a).cross(c - a).normalized();
    const auto count = static_cast<std::size_t>(std::ceil(TriangleArea(mesh.vertices, t) / (spacing * spacing)));
    for (std::size_t i = 0; i < count; ++i) {
      float u = unit(random), v = unit(random);
      if (u + v > 1.0F) {  // folded back into the triangle: uniform over its area
        u = 1.0F - u;
        v = 1.0F - v;
      }
      samples.points.push_back(a + u * (b - a) + v * (c - a));
      samples.normals.push_back(normal);
    }
  }
  return samples;
}

// Which samples some view saw: in its image and range, facing it, and at the depth it measured there.
std::vector<std::uint8_t> SeenSamples(const SurfaceSamples& samples, const DenseTruth& truth,
                                      const DenseScoreOptions& options) {
  std::vector<std::uint8_t> seen(samples.points.size(), 0);
  const core::CameraIntrinsics& camera = truth.camera;
  for (const DenseTruth::View& view : truth.views) {
    const core::Pose T_cw = view.T_wc.inverse();
    const Eigen::Vector3f centre = view.T_wc.translation().cast<float>();
    for (std::size_t i = 0; i < samples.points.size(); ++i) {
      if (seen[i] != 0) continue;
      const Eigen::Vector3d p_c = T_cw * samples.points[i].cast<double>();
      if (p_c.z() < options.min_depth || p_c.z() > options.max_depth) continue;
      const Eigen::Vector2d pixel = camera.Project(p_c);
      const int u = static_cast<int>(pixel.x()), v = static_cast<int>(pixel.y());
      if (pixel.x() < 0 || pixel.y() < 0 || u >= view.depth.cols || v >= view.depth.rows) continue;
      if (samples.normals[i].dot(samples.points[i] - centre) >= 0.0F) continue;  // from behind: inside a box
      const double measured = view.depth.at<float>(v, u);
      const double tolerance = std::max(kVisibilityTolerance, 3.0 * core::KinectDepthSigma(p_c.z()));
      if (measured > 0.0 && std::abs(measured - p_c.z()) <= tolerance) seen[i] = 1;
    }
  }
  return seen;
}

}  // namespace

bool DenseTruth::Exists(const std::filesystem::path& sequence) {
  return std::filesystem::is_regular_file(sequence / "static_geometry.ply") &&
         std::filesystem::is_regular_file(sequence / "moving_volume.ply");
}

DenseTruth DenseTruth::Load(const io::RgbdSequence& sequence, const core::CameraIntrinsics& camera,
                            std::size_t view_step) {
  DenseTruth truth;
  truth.static_geometry = io::ReadPlyMesh(sequence.root() / "static_geometry.ply");
  truth.moving_volume = io::ReadVoxelCentresPly(sequence.root() / "moving_volume.ply");
  truth.camera = camera;
  const core::Trajectory& path = sequence.groundtruth();
  if (path.empty()) throw core::InputError::InFile(sequence.root() / "groundtruth.txt", "missing or empty");
  for (std::size_t i = 0; i < sequence.size(); i += std::max<std::size_t>(view_step, 1)) {
    const double stamp = sequence.entry(i).rgb_timestamp;
    const auto after = std::lower_bound(path.begin(), path.end(), stamp,
                                        [](const core::StampedPose& p, double t) { return p.timestamp < t; });
    auto nearest = after;
    if (after == path.end() || (after != path.begin() && stamp - std::prev(after)->timestamp < after->timestamp - stamp)) {
      nearest = std::prev(after);
    }
    if (std::abs(nearest->timestamp - stamp) > kPoseTolerance) continue;  // a frame without a true pose
    truth.views.push_back({nearest->T_wc, sequence.LoadFrame(i).depth});
  }
  return truth;
}

DenseScore ScoreDenseMap(const io::TriangleMesh& reconstruction, const std::vector<Eigen::Vector3d>* occupied,
                         double occupancy_resolution, const Alignment& alignment, const DenseTruth& truth,
                         const DenseScoreOptions& options) {
  DenseScore score;
  Surface static_surface(truth.static_geometry);

  io::TriangleMesh aligned = reconstruction;
  for (Eigen::Vector3f& v : aligned.vertices) v = alignment.Apply(v.cast<double>()).cast<float>();
  const std::vector<float> vertex_distances = static_surface.Distances(aligned.vertices);
  if (!vertex_distances.empty()) {
    double sum = 0.0;
    for (const float d : vertex_distances) sum += d;
    score.accuracy_mean = sum / static_cast<double>(vertex_distances.size());
    score.accuracy_median = Percentile(vertex_distances, 0.5);
    score.accuracy_p90 = Percentile(vertex_distances, 0.9);
  }

  std::vector<Eigen::Vector3f> centroids;
  centroids.reserve(aligned.triangles.size());
  for (const Eigen::Vector3i& t : aligned.triangles) {
    centroids.push_back((aligned.vertices[t[0]] + aligned.vertices[t[1]] + aligned.vertices[t[2]]) / 3.0F);
  }
  const std::vector<float> centroid_distances = static_surface.Distances(centroids);
  for (std::size_t i = 0; i < aligned.triangles.size(); ++i) {
    const double area = TriangleArea(aligned.vertices, aligned.triangles[i]);
    score.area += area;
    if (centroid_distances[i] > options.ghost_distance) score.ghost_area += area;
  }

  const SurfaceSamples samples = SampleSurface(truth.static_geometry, options.surface_spacing);
  const std::vector<std::uint8_t> seen = SeenSamples(samples, truth, options);
  std::vector<Eigen::Vector3f> seen_points;
  for (std::size_t i = 0; i < seen.size(); ++i) {
    if (seen[i] != 0) seen_points.push_back(samples.points[i]);
  }
  score.seen_samples = seen_points.size();
  Surface reconstructed(aligned);
  const std::vector<float> to_reconstruction = reconstructed.Distances(seen_points);
  if (!seen_points.empty()) {
    const auto mapped = std::count_if(to_reconstruction.begin(), to_reconstruction.end(),
                                      [&](float d) { return d <= options.completeness_distance; });
    score.completeness = static_cast<double>(mapped) / static_cast<double>(seen_points.size());
  }

  if (occupied != nullptr) {
    std::unordered_set<std::uint64_t> moving;
    for (const Eigen::Vector3f& c : truth.moving_volume.centres) {
      moving.insert(io::CellKeyOf(c.cast<double>(), truth.moving_volume.voxel_size));
    }
    std::vector<Eigen::Vector3f> in_moving_volume;
    for (const Eigen::Vector3d& cell : *occupied) {
      const Eigen::Vector3d p = alignment.Apply(cell);
      if (moving.contains(io::CellKeyOf(p, truth.moving_volume.voxel_size))) {
        in_moving_volume.push_back(p.cast<float>());
      }
    }
    const std::vector<float> to_static = static_surface.Distances(in_moving_volume);
    score.occupied_cells = occupied->size();
    score.ghost_cells = static_cast<std::size_t>(std::count_if(
        to_static.begin(), to_static.end(), [&](float d) { return d > occupancy_resolution; }));
  }
  return score;
}

Alignment DenseScoreAlignment(const core::Trajectory& groundtruth, const core::Trajectory& keyframes,
                              const AssociationOptions& association, const DenseScoreOptions& options) {
  return AlignPoses(groundtruth, keyframes, association, options.AlignmentLever());
}

nlohmann::json DenseScoreJson(const DenseScore& score, const DenseScoreOptions& options) {
  nlohmann::json json = {
      {"accuracy_m", {{"mean", score.accuracy_mean}, {"median", score.accuracy_median}, {"p90", score.accuracy_p90}}},
      {"completeness", score.completeness},
      {"seen_samples", score.seen_samples},
      {"area_m2", score.area},
      {"ghost_area_m2", score.ghost_area},
      {"ghost_share", score.GhostShare()},
      {"occupied_cells", nullptr},
      {"ghost_cells", nullptr},
      {"options",
       {{"completeness_distance", options.completeness_distance},
        {"ghost_distance", options.ghost_distance},
        {"surface_spacing", options.surface_spacing},
        {"view_step", options.view_step},
        {"aligned_by", "keyframe poses"},
        {"alignment_lever_m", options.AlignmentLever()}}},
  };
  if (score.occupied_cells) json["occupied_cells"] = *score.occupied_cells;
  if (score.ghost_cells) json["ghost_cells"] = *score.ghost_cells;
  return json;
}

}  // namespace hoidslam::eval
