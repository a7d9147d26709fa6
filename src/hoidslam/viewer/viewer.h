#pragma once
// The live viewer: a web server in threads of its own that shows a page (web/, built into static files) with the
// map, the current frame and the run's controls (docs/viewer.md). The run hands it a snapshot after each frame
// (latest wins: publishing swaps a pointer) and a way to read the map, which the viewer's own thread copies a few
// times a second; pages are sent what changed by server-sent events. A slow or closed page never holds the run up:
// each page's connection is served in a thread of the server's pool, and takes the newest there is when it is
// ready. Tracking never knows the viewer exists. A dense map, when the run makes one, is handed over as a mesh.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "hoidslam/core/camera.h"
#include "hoidslam/core/shipped_dir.h"
#include "hoidslam/io/ply_file.h"
#include "hoidslam/pipeline/playback.h"
#include "hoidslam/pipeline/session.h"
#include "hoidslam/slam/system.h"
#include "hoidslam/viewer/frame_snapshot.h"

namespace hoidslam::viewer {

struct ViewerOptions {
  std::string address = "127.0.0.1";  // where the server listens; 0.0.0.0 shows the page to other machines too
  int port = 8787;                     // 0: a free port the system picks
  std::filesystem::path web_dir = core::WebDir();
  double image_scale = 0.5;  // the frame's image is sent at this fraction of its size (keypoints stay exact)
  int jpeg_quality = 80;
  double map_interval_s = 0.25;  // how often the map is read while the run goes

  // Throws InputError naming --view-port / --view-address / the web folder.
  void Check() const;
};

// What a page is told once, when it connects.
struct ViewerHello {
  std::string sequence;
  std::size_t total_frames = 0;  // 0: not known (a live camera)
  core::CameraIntrinsics camera;
};

class Viewer {
 public:
  // Listens and serves until destroyed. `playback` (may be null: the run cannot be paused) is what the page's
  // controls set; it must outlive the viewer. Throws InputError when the options fail Check() or the address and
  // port cannot be listened on.
  Viewer(const ViewerOptions& options, const ViewerHello& hello, pipeline::Playback* playback);
  ~Viewer();  // stops serving: pages see the connection end
  Viewer(const Viewer&) = delete;
  Viewer& operator=(const Viewer&) = delete;

  // http://address:port/
  std::string url() const;

  // The newest frame (latest wins).
  void Publish(FrameSnapshot snapshot);
  // A run starts: reads its map with `read` a few times a second, in the viewer's thread, until FinalMap. `read`
  // must be safe to call from another thread while the run goes (slam::System::ViewAtlas is).
  void FollowMap(std::function<slam::AtlasView()> read);
  // The map as the run's outputs have it; `main_map` is the map they write. Stops following; returns when no read
  // is under way, so the object `read` reads may go.
  void FinalMap(const slam::AtlasView& atlas, slam::MapId main_map);
  // The same for a session (pipeline::Session): its map is followed until FinalMapOf, which shows it as the session
  // writes it (its main map) and must come before the session goes.
  void FollowSession(const pipeline::Session& session);
  void FinalMapOf(const pipeline::Session& session);
  // The dense map to show with the sparse one (latest wins: a newer mesh replaces it on every page). The mesh is
  // encoded here, once, and sent to each page as a `dense` event; keep it small (dense::MeshForDisplay).
  void ShowDenseMap(const io::TriangleMesh& mesh);
  // The run's outputs are written: pages say so.
  void RunFinished();

  // How many frames the pages were sent (all pages together): a test's measure of the page updates.
  std::uint64_t FramesSent() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hoidslam::viewer
