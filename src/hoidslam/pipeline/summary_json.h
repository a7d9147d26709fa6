#pragma once
// summary.json of a run folder (docs/slam.md, "Outputs"): the counts, timings, loops and maps of a run, and how it
// was made. Written by `hoidslam run` and by the API's System::Save, so that `hoidslam report` and `bench` read
// either.

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "hoidslam/io/settings.h"
#include "hoidslam/pipeline/run.h"

namespace hoidslam::pipeline {

// Everything but the evaluation against ground truth and the provenance.
nlohmann::json RunSummaryJson(const RunSummary& s, const std::string& sequence, const std::string& mode,
                              const std::string& detector, const RealTimeOptions& realtime);

// How a run was made, for whoever reads its folder later.
struct Provenance {
  nlohmann::json command_line = nullptr;  // {"argv", "working_directory"} of the command; null from the API
  std::string version;                    // hoidslam's
  std::filesystem::path settings_file;    // empty: none (the defaults, or a camera given by its values)
  std::string settings_chosen;            // io::ToString(SettingsChoice::Reason), or "camera" from the API
  io::Settings settings;                  // every value as used
  std::filesystem::path vocabulary;
  std::string vocabulary_identity;        // RunSummary::vocabulary_identity
  std::filesystem::path detector_source;  // a model or detections file (detect::Detector::Source); empty: none
};
// {"command_line", "version", "settings": {"file", "chosen", "values"}, "vocabulary": {"file", "identity"},
// "detector_source": {"file", "sha256"} or null}. Reads the detector's file (InputError naming it when it cannot be
// read).
nlohmann::json ProvenanceJson(const Provenance& provenance);

}  // namespace hoidslam::pipeline
