#include "hoidslam/viewer/viewer.h"

#include <httplib.h>

#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "hoidslam/core/error.h"
#include "hoidslam/report/page_json.h"
#include "hoidslam/viewer/atlas_history.h"

namespace hoidslam::viewer {
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

// One server-sent event.
std::string Event(std::string_view name, std::string_view data) {
  return fmt::format("event: {}\ndata: {}\n\n", name, data);
}

}  // namespace

void ViewerOptions::Check() const {
  if (port < 0 || port > 65535) {
    throw core::InputError::ForParameter("--view-port", fmt::format("must be in [0, 65535], got {}", port));
  }
  if (address.empty()) throw core::InputError::ForParameter("--view-address", "is empty");
  if (!std::filesystem::exists(web_dir / "index.html")) {
    throw core::InputError::InFile(web_dir / "index.html",
                                   "the viewer's page is not there: build hoidslam with scripts/setup.sh (it bundles "
                                   "the page from web/ with npm)");
  }
  if (!(image_scale > 0.0 && image_scale <= 1.0)) {
    throw core::InputError::ForParameter("image_scale", fmt::format("must be in (0, 1], got {}", image_scale));
  }
  if (jpeg_quality < 1 || jpeg_quality > 100) {
    throw core::InputError::ForParameter("jpeg_quality", fmt::format("must be in [1, 100], got {}", jpeg_quality));
  }
  if (!(map_interval_s > 0.0)) {
    throw core::InputError::ForParameter("map_interval_s", fmt::format("must be > 0, got {}", map_interval_s));
  }
}

class Viewer::Impl {
 public:
  Impl(const ViewerOptions& options, const ViewerHello& hello, pipeline::Playback* playback)
      : options_(options), playback_(playback) {
    options_.Check();
    hello_json_ = report::HelloJson(hello.sequence, hello.total_frames, hello.camera, playback != nullptr).dump();
    total_frames_ = hello.total_frames;
    Route();
    port_ = options_.port == 0 ? server_.bind_to_any_port(options_.address)
                               : (server_.bind_to_port(options_.address, options_.port) ? options_.port : -1);
    if (port_ < 0) {
      throw core::InputError::ForParameter(
          options_.port == 0 ? "--view-address" : "--view-port",
          fmt::format("cannot listen on {}:{}: the address is not this machine's or the port is taken (--view-port 0 "
                      "picks a free one)",
                      options_.address, options_.port));
    }
    listener_ = std::thread([this] { server_.listen_after_bind(); });
    // stop() before the server runs would be lost, and the listener never end.
    while (!server_.is_running()) std::this_thread::sleep_for(1ms);
    map_reader_ = std::thread([this] { ReadMapUntilStopped(); });
  }

  ~Impl() {
    {
      const std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    changed_.notify_all();
    map_wake_.notify_all();
    server_.stop();
    listener_.join();
    map_reader_.join();
  }

  std::string url() const {
    return fmt::format("http://{}:{}/", options_.address == "0.0.0.0" ? "127.0.0.1" : options_.address, port_);
  }

  void Publish(FrameSnapshot snapshot) {
    auto shared = std::make_shared<const FrameSnapshot>(std::move(snapshot));
    {
      const std::lock_guard lock(mutex_);
      const Clock::time_point now = Clock::now();
      arrivals_.push_back(now);
      while (now - arrivals_.front() > 1s) arrivals_.pop_front();
      if (shared->T_wc) current_map_ = shared->entry.value("map", current_map_);
      frames_done_ = shared->index + 1;
      frame_ = {std::move(shared), static_cast<double>(arrivals_.size())};
      ++frame_sequence_;
      ++status_sequence_;
    }
    changed_.notify_all();
  }

  void FollowMap(std::function<slam::AtlasView()> read) {
    {
      const std::lock_guard lock(read_mutex_);
      read_ = std::move(read);
    }
    const std::lock_guard lock(mutex_);
    finished_ = false;
    ++status_sequence_;
  }

  void FinalMap(const slam::AtlasView& atlas, slam::MapId main_map) {
    {
      const std::lock_guard lock(read_mutex_);  // waits for a read under way
      read_ = nullptr;
    }
    UpdateMap(atlas, main_map);
  }

  void ShowDenseMap(const io::TriangleMesh& mesh) {
    auto json = std::make_shared<const std::string>(report::DenseMeshJson(mesh).dump());
    {
      const std::lock_guard lock(mutex_);
      dense_json_ = std::move(json);
      ++dense_sequence_;
    }
    changed_.notify_all();
  }

  void RunFinished() {
    {
      const std::lock_guard lock(mutex_);
      finished_ = true;
      ++status_sequence_;
    }
    changed_.notify_all();
  }

  std::uint64_t FramesSent() const {
    const std::lock_guard lock(mutex_);
    return frames_sent_;
  }

 private:
  // What one page's connection has been sent.
  struct Connection {
    bool greeted = false;
    std::uint64_t frame = 0;     // sequence number of the last frame sent (0: none)
    std::uint64_t revision = 0;  // of the map
    std::uint64_t status = 0;
    std::uint64_t dense = 0;     // sequence number of the last dense map sent (0: none)
  };

  void Route() {
    server_.new_task_queue = [] { return new httplib::ThreadPool(kServerThreads); };
    server_.set_keep_alive_timeout(1);  // an idle connection holds a thread of the pool
    // The library's default also shares the port with another server (SO_REUSEPORT): a port in use must be said.
    server_.set_socket_options([](socket_t socket) {
      const int yes = 1;
      setsockopt(socket, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
    });
    server_.set_mount_point("/", options_.web_dir.string());
    server_.Get("/events", [this](const httplib::Request&, httplib::Response& response) {
      response.set_header("Cache-Control", "no-store");
      auto connection = std::make_shared<Connection>();
      response.set_chunked_content_provider("text/event-stream", [this, connection](std::size_t, httplib::DataSink& sink) {
        return SendNews(*connection, sink);
      });
    });
    server_.Post("/control", [this](const httplib::Request& request, httplib::Response& response) {
      Control(request.body, response);
    });
  }

  // Waits up to a second for something newer than `connection` has, and sends it; a comment when nothing came, so
  // that a closed page is noticed. When the viewer stops, the stream is ended properly (the page then sees a
  // closed stream, not a broken one). False ends the connection.
  bool SendNews(Connection& connection, httplib::DataSink& sink) {
    std::shared_ptr<const FrameSnapshot> frame;
    std::shared_ptr<const std::string> dense;
    double fps = 0.0;
    std::uint64_t frame_sequence = 0, revision = 0, status_sequence = 0, dense_sequence = 0;
    {
      std::unique_lock lock(mutex_);
      changed_.wait_for(lock, 1s, [&] {
        return stopping_ || !connection.greeted || connection.frame != frame_sequence_ ||
               connection.revision != revision_ || connection.status != status_sequence_ ||
               connection.dense != dense_sequence_;
      });
      if (stopping_) {
        sink.done();
        return true;
      }
      std::tie(frame, fps) = frame_;
      frame_sequence = frame_sequence_;
      revision = revision_;
      status_sequence = status_sequence_;
      dense = dense_json_;
      dense_sequence = dense_sequence_;
    }
    std::string news;
    if (!connection.greeted) {
      news += Event("hello", hello_json_);
      connection.greeted = true;
    }
    if (connection.revision != revision) {
      const std::lock_guard lock(history_mutex_);
      news += Event("map", history_.EventJsonSince(connection.revision));
      connection.revision = history_.revision();
    }
    if (dense && connection.dense != dense_sequence) {
      news += Event("dense", *dense);
      connection.dense = dense_sequence;
    }
    if (frame && connection.frame != frame_sequence) {
      news += Event("frame", FrameJson(frame, frame_sequence, fps));
      connection.frame = frame_sequence;
      const std::lock_guard lock(mutex_);
      ++frames_sent_;
    }
    if (connection.status != status_sequence) {
      news += Event("status", Status().dump());
      connection.status = status_sequence;
    }
    if (news.empty()) news = ": nothing new\n\n";
    return sink.write(news.data(), news.size());
  }

  // The frame's JSON, made once however many pages want it.
  std::string FrameJson(const std::shared_ptr<const FrameSnapshot>& frame, std::uint64_t sequence, double fps) {
    const std::lock_guard lock(frame_json_mutex_);
    if (frame_json_sequence_ != sequence) {
      frame_json_ = FrameEventJson(*frame, fps, options_.image_scale, options_.jpeg_quality);
      frame_json_sequence_ = sequence;
    }
    return frame_json_;
  }

  nlohmann::json Status() const {
    const pipeline::Playback::State playback = playback_ != nullptr ? playback_->state() : pipeline::Playback::State{};
    const std::lock_guard lock(mutex_);
    return nlohmann::json{{"state", finished_ ? "finished" : "running"},
                          {"paused", playback.paused},
                          {"speed", playback.speed},
                          {"frames_done", frames_done_},
                          {"total_frames", total_frames_}};
  }

  void Control(const std::string& body, httplib::Response& response) {
    const auto answer = [&response](int status, nlohmann::json json) {
      response.status = status;
      response.set_content(json.dump(), "application/json");
    };
    if (playback_ == nullptr) {
      answer(409, {{"ok", false}, {"error", "this run cannot be paused: it is paced by the recording or live"}});
      return;
    }
    try {
      const nlohmann::json request = nlohmann::json::parse(body);
      const std::string command = request.at("command").get<std::string>();
      if (command == "pause") {
        playback_->Pause();
      } else if (command == "play") {
        playback_->Play();
      } else if (command == "step") {
        playback_->Step();
      } else if (command == "speed") {
        playback_->SetSpeed(request.at("speed").get<double>());
      } else {
        answer(400, {{"ok", false}, {"error", fmt::format("unknown command '{}' (pause, play, step, speed)", command)}});
        return;
      }
    } catch (const std::exception& e) {  // not JSON, a field missing or of the wrong type, a speed out of range
      answer(400, {{"ok", false}, {"error", e.what()}});
      return;
    }
    {
      const std::lock_guard lock(mutex_);
      ++status_sequence_;
    }
    changed_.notify_all();
    nlohmann::json status = Status();
    status["ok"] = true;
    answer(200, std::move(status));
  }

  void ReadMapUntilStopped() {
    const auto interval = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options_.map_interval_s));
    while (true) {
      {
        std::unique_lock lock(mutex_);
        map_wake_.wait_for(lock, interval, [this] { return stopping_; });
        if (stopping_) return;
      }
      std::optional<slam::AtlasView> atlas;
      {
        const std::lock_guard lock(read_mutex_);
        if (read_) atlas = read_();
      }
      if (atlas) UpdateMap(*atlas, CurrentMap());
    }
  }

  slam::MapId CurrentMap() const {
    const std::lock_guard lock(mutex_);
    return current_map_;
  }

  void UpdateMap(const slam::AtlasView& atlas, slam::MapId main_map) {
    std::uint64_t revision = 0;
    {
      const std::lock_guard lock(history_mutex_);
      if (!history_.Update(atlas, main_map)) return;
      revision = history_.revision();
    }
    {
      const std::lock_guard lock(mutex_);
      revision_ = revision;
    }
    changed_.notify_all();
  }

  static constexpr int kServerThreads = 16;  // each open page holds one for its events

  ViewerOptions options_;
  pipeline::Playback* playback_;
  std::string hello_json_;
  std::size_t total_frames_ = 0;
  httplib::Server server_;
  int port_ = -1;
  std::thread listener_;
  std::thread map_reader_;

  // What the pages are sent, and when there is news.
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::condition_variable map_wake_;
  bool stopping_ = false;
  bool finished_ = false;
  std::pair<std::shared_ptr<const FrameSnapshot>, double> frame_{nullptr, 0.0};  // the newest, and the fps then
  std::uint64_t frame_sequence_ = 0;
  std::deque<Clock::time_point> arrivals_;  // of the frames of the last second
  std::size_t frames_done_ = 0;
  slam::MapId current_map_ = 0;
  std::uint64_t revision_ = 0;  // the history's
  std::uint64_t status_sequence_ = 0;
  std::uint64_t frames_sent_ = 0;
  std::shared_ptr<const std::string> dense_json_;  // the newest dense map's event data, made once for every page
  std::uint64_t dense_sequence_ = 0;

  std::mutex history_mutex_;
  AtlasHistory history_;

  std::mutex frame_json_mutex_;
  std::uint64_t frame_json_sequence_ = 0;
  std::string frame_json_;

  std::mutex read_mutex_;
  std::function<slam::AtlasView()> read_;
};

Viewer::Viewer(const ViewerOptions& options, const ViewerHello& hello, pipeline::Playback* playback)
    : impl_(std::make_unique<Impl>(options, hello, playback)) {}
Viewer::~Viewer() = default;
std::string Viewer::url() const { return impl_->url(); }
void Viewer::Publish(FrameSnapshot snapshot) { impl_->Publish(std::move(snapshot)); }
void Viewer::FollowMap(std::function<slam::AtlasView()> read) { impl_->FollowMap(std::move(read)); }
void Viewer::FinalMap(const slam::AtlasView& atlas, slam::MapId main_map) { impl_->FinalMap(atlas, main_map); }
void Viewer::FollowSession(const pipeline::Session& session) {
  FollowMap([&session] { return session.system().ViewAtlas(); });
}
void Viewer::FinalMapOf(const pipeline::Session& session) {
  FinalMap(session.system().ViewAtlas(), session.summary().main_map);
}
void Viewer::ShowDenseMap(const io::TriangleMesh& mesh) { impl_->ShowDenseMap(mesh); }
void Viewer::RunFinished() { impl_->RunFinished(); }
std::uint64_t Viewer::FramesSent() const { return impl_->FramesSent(); }

}  // namespace hoidslam::viewer
