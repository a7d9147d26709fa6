// Tracks a TUM-style folder through hoidslam's library, as a camera program would hand it frames: reads
// associations.txt (`t_rgb rgb/... t_depth depth/...` lines), tracks each pair, prints every pose and saves the
// trajectory, keyframes and map.
//
//   track_folder FOLDER OUT [--settings S.yaml] [--camera fx,fy,cx,cy,width,height --depth-scale S] [--model M.onnx]
//
// --camera gives the camera by its values, as a camera SDK reports them, with --depth-scale its metres per unit of
// 16-bit depth (0.001 for millimetres, 0.0002 for TUM's files). With a model the ONNX detector finds people and
// the default filter (hoidplus) drops them; without one, the filter is none.
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include <opencv2/imgcodecs.hpp>

#include "hoidslam/hoidslam.h"
#include "hoidslam/hoidslam_opencv.h"
#include "hoidslam/version.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr,
                 "usage: track_folder FOLDER OUT [--settings S.yaml] [--camera fx,fy,cx,cy,width,height "
                 "--depth-scale S] [--model M.onnx]\n");
    return 2;
  }
  const std::string folder = argv[1];
  hoidslam::Options options;
  options.filter = "none";
  options.detector = hoidslam::DetectorKind::kNone;
  double depth_scale = hoidslam::Camera{}.depth_scale;
  for (int i = 3; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--settings") options.settings = argv[i + 1];
    if (flag == "--camera") {
      hoidslam::Camera camera;
      char comma = ',';
      std::istringstream values(argv[i + 1]);
      values >> camera.fx >> comma >> camera.fy >> comma >> camera.cx >> comma >> camera.cy >> comma >>
          camera.width >> comma >> camera.height;
      options.camera = camera;
    }
    if (flag == "--depth-scale") depth_scale = std::stod(argv[i + 1]);
    if (flag == "--model") {
      options.filter = "";  // the settings' HOID.mode, else hoidplus
      options.detector = hoidslam::DetectorKind::kOnnx;
      options.model = argv[i + 1];
    }
  }
  if (options.camera) options.camera->depth_scale = depth_scale;
  std::printf("hoidslam %s (headers %s)\nshipped files: %s\n", hoidslam::Version().c_str(), HOIDSLAM_VERSION,
              hoidslam::ShippedDir().c_str());
  try {
    hoidslam::System slam(options);
    std::ifstream associations(folder + "/associations.txt");
    if (!associations) throw hoidslam::InputError(folder + "/associations.txt: cannot open");
    std::size_t tracked = 0, frames = 0;
    for (std::string line; std::getline(associations, line);) {
      if (line.empty() || line[0] == '#') continue;
      std::istringstream fields(line);
      double t = 0.0, t_depth = 0.0;
      std::string rgb_file, depth_file;
      fields >> t >> rgb_file >> t_depth >> depth_file;
      const cv::Mat rgb = cv::imread(folder + "/" + rgb_file, cv::IMREAD_COLOR);
      const cv::Mat depth = cv::imread(folder + "/" + depth_file, cv::IMREAD_UNCHANGED);
      // The depth image may be taken apart from the colour one (TUM fr1: up to 20 ms): tell the safety net.
      const hoidslam::FrameResult r =
          hoidslam::Track(slam, rgb, depth, t, {}, hoidslam::PixelFormat::kBgr, t_depth - t);
      ++frames;
      if (r.T_wc) {
        ++tracked;
        const hoidslam::Matrix4& T = *r.T_wc;
        std::printf("%.6f %s position %.4f %.4f %.4f, %zu of %zu keypoints kept\n", t,
                    std::string(hoidslam::ToString(r.state)).c_str(), T[3], T[7], T[11],
                    r.keypoints.size() - r.dropped, r.keypoints.size());
      } else {
        std::printf("%.6f %s\n", t, std::string(hoidslam::ToString(r.state)).c_str());
      }
    }
    slam.Save(argv[2]);
    std::printf("%zu of %zu frames tracked; %zu keyframes, %zu map points; wrote %s\n", tracked, frames,
                slam.KeyFrames().size(), slam.MapPoints().size(), argv[2]);
  } catch (const hoidslam::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
