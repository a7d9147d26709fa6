#pragma once
// A recorded sequence played as a live camera (`hoidslam run --pace`): the frames of live_pacing.h, decoded before
// their time comes. A camera hands out decoded images; a replay that decoded its PNG files on the way would charge
// hoidslam for the decoder (about half of a 30 Hz frame's time on a 2-core laptop) and drop frames a live camera
// would not. Frames are decoded in chunks that fit a memory budget, on all cores, with the clock held meanwhile:
// the first chunk before the camera starts, each further one when the run reaches it.

#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "hoidslam/core/frame.h"
#include "hoidslam/io/rgbd_sequence.h"
#include "hoidslam/pipeline/live_pacing.h"

namespace hoidslam::pipeline {

class PacedReplay {
 public:
  // Plays the first `frames` frames of `sequence`, which must outlive the replay, and decodes the first chunk.
  // `memory_budget_bytes`: how much the decoded frames of one chunk may take (at least one frame is decoded at a
  // time). Throws InputError naming the file of a frame that cannot be read.
  PacedReplay(const io::RgbdSequence& sequence, std::size_t frames, std::size_t memory_budget_bytes);

  // The frame to process after frame `previous` (nullopt: the first), as LivePacing::Next, decoded and ready
  // for Take. nullopt when the sequence is over or `stop_requested` says so. Throws as the constructor.
  std::optional<std::size_t> Next(std::optional<std::size_t> previous, const std::function<bool()>& stop_requested);
  // Frame `index` as Next returned it; each frame can be taken once.
  core::RgbdFrame Take(std::size_t index);

  std::size_t dropped() const { return pacing_.dropped(); }
  std::size_t chunks_decoded() const { return chunks_decoded_; }
  // How long the clock was held for decoding after the first chunk (seconds).
  double held_seconds() const { return held_seconds_; }

 private:
  // Decodes the frames from `first` on, as many as the budget allows.
  void DecodeChunk(std::size_t first);

  const io::RgbdSequence& sequence_;
  std::size_t frames_;
  std::size_t memory_budget_bytes_;
  LivePacing pacing_;
  std::size_t chunk_first_ = 0;
  std::vector<core::RgbdFrame> chunk_;
  std::size_t chunks_decoded_ = 0;
  double held_seconds_ = 0.0;
};

}  // namespace hoidslam::pipeline
