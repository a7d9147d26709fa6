#include "hoidslam/pipeline/paced_replay.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <stdexcept>
#include <thread>

#include <spdlog/spdlog.h>

#include "hoidslam/core/stopwatch.h"

namespace hoidslam::pipeline {
namespace {

std::size_t FrameBytes(const core::RgbdFrame& frame) {
  return frame.rgb.total() * frame.rgb.elemSize() + frame.depth.total() * frame.depth.elemSize();
}

}  // namespace

PacedReplay::PacedReplay(const io::RgbdSequence& sequence, std::size_t frames, std::size_t memory_budget_bytes)
    : sequence_(sequence),
      frames_(std::min(frames, sequence.size())),
      memory_budget_bytes_(memory_budget_bytes),
      pacing_([&] {
        std::vector<double> timestamps = sequence.Timestamps();
        timestamps.resize(frames_);
        return timestamps;
      }()) {
  if (frames_ > 0) DecodeChunk(0);
}

std::optional<std::size_t> PacedReplay::Next(std::optional<std::size_t> previous,
                                             const std::function<bool()>& stop_requested) {
  const std::optional<std::size_t> next = pacing_.Next(previous, stop_requested);
  if (next && *next >= chunk_first_ + chunk_.size()) {
    const auto start = std::chrono::steady_clock::now();
    DecodeChunk(*next);
    const auto held = std::chrono::steady_clock::now() - start;
    pacing_.Hold(held);
    held_seconds_ += std::chrono::duration<double>(held).count();
  }
  return next;
}

core::RgbdFrame PacedReplay::Take(std::size_t index) {
  if (index < chunk_first_ || index >= chunk_first_ + chunk_.size() || chunk_[index - chunk_first_].rgb.empty()) {
    throw std::logic_error("PacedReplay::Take: frame " + std::to_string(index) + " is not ready");
  }
  return std::move(chunk_[index - chunk_first_]);
}

void PacedReplay::DecodeChunk(std::size_t first) {
  const core::Stopwatch clock;
  chunk_.clear();  // the frames taken or dropped so far are released first
  chunk_first_ = first;
  core::RgbdFrame first_frame = sequence_.LoadFrame(first);
  const std::size_t frame_bytes = std::max<std::size_t>(1, FrameBytes(first_frame));
  const std::size_t count = std::clamp<std::size_t>(memory_budget_bytes_ / frame_bytes, 1, frames_ - first);
  chunk_.resize(count);
  chunk_[0] = std::move(first_frame);

  // Frames 1..count-1 on every core; the error of the earliest frame that fails is the one reported.
  std::atomic<std::size_t> next_frame{1};
  std::vector<std::exception_ptr> errors(count);
  {
    std::vector<std::jthread> workers;
    const unsigned threads = std::max(1U, std::thread::hardware_concurrency());
    for (unsigned t = 0; t < threads && t + 1 < count; ++t) {
      workers.emplace_back([&] {
        for (std::size_t i; (i = next_frame.fetch_add(1)) < count;) {
          try {
            chunk_[i] = sequence_.LoadFrame(first + i);
          } catch (...) {
            errors[i] = std::current_exception();
          }
        }
      });
    }
  }
  for (const std::exception_ptr& error : errors) {
    if (error) std::rethrow_exception(error);
  }
  ++chunks_decoded_;
  spdlog::info("paced replay: frames {}-{} decoded ahead ({:.2f} GB in {:.1f} s){}", first, first + count - 1,
               static_cast<double>(count * frame_bytes) / 1e9, clock.ElapsedMilliseconds() / 1000.0,
               first > 0 ? ", the camera's clock held meanwhile" : "");
}

}  // namespace hoidslam::pipeline
