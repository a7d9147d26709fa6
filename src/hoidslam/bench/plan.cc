#include "hoidslam/bench/plan.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "hoidslam/core/error.h"
#include "hoidslam/core/options.h"
#include "hoidslam/io/files.h"
#include "hoidslam/io/rgbd_sequence.h"
#include "hoidslam/io/settings.h"

namespace hoidslam::bench {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kModes = {"none", "person", "classes", "hoid2d", "hoid3d", "hoidplus", "oracle"};

bool Contains(const std::vector<std::string>& list, const std::string& value) {
  return std::find(list.begin(), list.end(), value) != list.end();
}

bool SameValue(double a, double b) { return std::abs(a - b) < 1e-9; }

// Shortest text that reads back as the same double: 0.3, not 0.29999999999999999.
std::string Number(double value) { return fmt::format("{}", value); }

// Index of `variant` in `variants`, appended when new.
std::size_t VariantIndex(std::vector<Variant>& variants, const Variant& variant) {
  const auto found = std::find(variants.begin(), variants.end(), variant);
  if (found != variants.end()) return static_cast<std::size_t>(found - variants.begin());
  variants.push_back(variant);
  return variants.size() - 1;
}

}  // namespace

void BenchOptions::Check() const {
  if (modes.empty()) throw core::InputError::ForParameter("--modes", "needs at least one mode");
  for (const std::string& mode : modes) {
    if (mode.starts_with(core::kHoidPlusPartsPrefix)) {
      core::HoidPlusOptions().SetParts(std::string_view(mode).substr(core::kHoidPlusPartsPrefix.size()), "--modes");
    } else if (!Contains(kModes, mode)) {
      throw core::InputError::ForParameter(
          "--modes",
          fmt::format("unknown mode '{}': use none, person, classes, hoid2d, hoid3d, hoidplus[:parts] or oracle", mode));
    }
  }
  if (runs == 0) throw core::InputError::ForParameter("--runs", "must be at least 1");
  for (const double area : area_sweep) {
    if (!(area > 0.0 && area <= 1.0)) {
      throw core::InputError::ForParameter("--area-sweep", fmt::format("{} is not in (0, 1]", area));
    }
  }
  for (const double depth : depth_sweep) {
    if (!(depth > 0.0)) throw core::InputError::ForParameter("--depth-sweep", fmt::format("{} is not > 0", depth));
  }
  if (realtime && deterministic) {
    throw core::InputError::ForParameter("--realtime", "cannot go with --deterministic");
  }
  if (!(detector_latency_ms >= 0.0)) throw core::InputError::ForParameter("--detector-latency", "must be >= 0 ms");
  if (synth_frame_step < 1) throw core::InputError::ForParameter("--synth-frame-step", "must be at least 1");
  if (!std::isfinite(random_duration) || random_duration < 0.0) {
    throw core::InputError::ForParameter("--random-duration", "must be >= 0 seconds");
  }
  if (!(timeout_seconds >= 0.0)) throw core::InputError::ForParameter("--timeout", "must be >= 0 seconds");
  if (!model.empty() && !fs::is_regular_file(model)) {
    throw core::InputError::ForParameter("--model", fmt::format("{}: no such file", model.string()));
  }
}

std::string Variant::Name() const {
  if (min_interaction_area) return fmt::format("{} area={}", mode, Number(*min_interaction_area));
  if (depth_threshold) return fmt::format("{} depth={}", mode, Number(*depth_threshold));
  return mode;
}

std::string Variant::Slug() const {
  if (min_interaction_area) return fmt::format("{}-area{}", mode, Number(*min_interaction_area));
  if (depth_threshold) return fmt::format("{}-depth{}", mode, Number(*depth_threshold));
  // "hoidplus:depth+memory" names a folder as hoidplus-depth-memory.
  std::string slug = mode;
  std::replace_if(slug.begin(), slug.end(), [](char c) { return c == ':' || c == '+'; }, '-');
  return slug;
}

std::vector<std::string> Plan::RunCommand(const RunSpec& spec) const {
  const BenchSequence& sequence = sequences.at(spec.sequence);
  const Variant& variant = variants.at(spec.variant);
  std::vector<std::string> command = {binary.string(), "run", sequence.path.string(), "--filter", variant.mode,
                                      "--out", RunFolder(spec).string(), "--force"};
  if (!sequence.settings.empty()) command.insert(command.end(), {"--settings", sequence.settings.string()});
  if (variant.min_interaction_area) {
    command.insert(command.end(), {"--min-interaction-area", Number(*variant.min_interaction_area)});
  }
  if (variant.depth_threshold) command.insert(command.end(), {"--depth-threshold", Number(*variant.depth_threshold)});
  if (options.frames > 0) command.insert(command.end(), {"--frames", std::to_string(options.frames)});
  if (options.deterministic) command.push_back("--deterministic");
  if (options.realtime) command.push_back("--realtime");
  if (options.pace) command.push_back("--pace");
  if (options.detector_latency_ms > 0) {
    command.insert(command.end(), {"--detector-latency", Number(options.detector_latency_ms)});
  }
  if (options.dense) command.push_back("--dense");
  const bool has_detections = fs::exists(sequence.path / "detections.jsonl") || sequence.Rendered();
  if (!options.model.empty() && !has_detections && variant.mode != "none" && variant.mode != "oracle") {
    command.insert(command.end(), {"--model", options.model.string()});
  }
  command.insert(command.end(), {"--snapshots", std::to_string(spec.run == 1 ? options.snapshots : 0)});
  return command;
}

std::vector<std::string> Plan::PrepareCommand(const BenchSequence& sequence) const {
  if (!sequence.Rendered()) return {};
  std::vector<std::string> command = {binary.string(), "synth"};
  if (sequence.random_seed) {
    command.insert(command.end(), {"--random", std::to_string(*sequence.random_seed)});
    if (options.random_duration > 0) {
      command.insert(command.end(), {"--random-duration", Number(options.random_duration)});
    }
    if (!options.textures.empty()) command.insert(command.end(), {"--textures", options.textures.string()});
  } else {
    command.insert(command.end(), {"--scenario", sequence.scenario});
  }
  command.insert(command.end(), {"--out", sequence.path.string()});
  if (options.synth_frames > 0) command.insert(command.end(), {"--frames", std::to_string(options.synth_frames)});
  if (options.synth_frame_step > 1) {
    command.insert(command.end(), {"--frame-step", std::to_string(options.synth_frame_step)});
  }
  return command;
}

std::optional<std::size_t> Plan::SweepVariant(const std::string& mode, double value, bool is_area,
                                              const BenchSequence& sequence) const {
  Variant wanted = Variant::Plain(mode);
  const double own = is_area ? sequence.min_interaction_area : sequence.depth_threshold;
  if (!SameValue(value, own)) (is_area ? wanted.min_interaction_area : wanted.depth_threshold) = value;
  const auto found = std::find(variants.begin(), variants.end(), wanted);
  if (found == variants.end()) return std::nullopt;
  return static_cast<std::size_t>(found - variants.begin());
}

Plan MakePlan(const BenchOptions& options, std::vector<BenchSequence> sequences, const fs::path& binary,
              const fs::path& folder) {
  options.Check();
  Plan plan;
  plan.options = options;
  plan.binary = fs::absolute(binary);
  plan.folder = fs::absolute(folder);
  plan.sequences = std::move(sequences);
  // The plain modes first, in the order asked, so the tables' columns follow it.
  for (const std::string& mode : options.modes) VariantIndex(plan.variants, Variant::Plain(mode));

  for (std::size_t s = 0; s < plan.sequences.size(); ++s) {
    const BenchSequence& sequence = plan.sequences[s];
    if (!sequence.problem.empty()) continue;
    std::vector<std::pair<std::size_t, std::size_t>> variants;  // index, runs
    for (const std::string& mode : options.modes) {
      if (mode == "oracle" && !sequence.has_masks) continue;  // needs ground-truth masks
      variants.emplace_back(VariantIndex(plan.variants, Variant::Plain(mode)), options.runs);
    }
    const auto add_sweep = [&](const std::string& mode, const std::vector<double>& values, bool is_area) {
      for (const double value : values) {
        const double own = is_area ? sequence.min_interaction_area : sequence.depth_threshold;
        if (SameValue(value, own) && Contains(options.modes, mode)) continue;  // the plain runs measure it
        Variant variant = Variant::Plain(mode);
        (is_area ? variant.min_interaction_area : variant.depth_threshold) = value;
        variants.emplace_back(VariantIndex(plan.variants, variant), options.SweepRuns());
      }
    };
    add_sweep("hoid2d", options.area_sweep, true);
    add_sweep("hoid3d", options.depth_sweep, false);
    for (const auto& [v, runs] : variants) {
      for (std::size_t run = 1; run <= runs; ++run) {
        plan.runs.push_back({.id = fmt::format("{}.{}.r{}", sequence.name, plan.variants[v].Slug(), run),
                             .sequence = s,
                             .variant = v,
                             .run = run});
      }
    }
  }
  return plan;
}

BenchSequence InspectSequence(std::string name, const fs::path& path, const fs::path& settings) {
  BenchSequence sequence;
  sequence.name = std::move(name);
  sequence.path = io::NormalFolder(path);
  sequence.settings = settings;
  core::HoidOptions hoid;
  try {
    io::SequenceOptions sequence_options;
    if (!settings.empty()) {
      const io::Settings loaded = io::LoadSettings(settings);
      hoid = loaded.hoid;
      sequence_options.depth_factor = loaded.depth_map_factor;
    }
    io::RgbdSequence::OpenTum(path, sequence_options);  // lists readable, every listed image present
  } catch (const core::InputError& e) {
    sequence.problem = e.what();
  }
  sequence.has_masks = fs::is_directory(path / "mask");
  sequence.min_interaction_area = hoid.min_interaction_area;
  sequence.depth_threshold = hoid.depth_threshold;
  return sequence;
}

nlohmann::json PlanToJson(const Plan& plan) {
  const BenchOptions& o = plan.options;
  nlohmann::json sequences = nlohmann::json::array();
  for (const BenchSequence& s : plan.sequences) {
    sequences.push_back({{"name", s.name},
                         {"path", s.path.string()},
                         {"scenario", s.scenario},
                         {"random_seed", s.random_seed ? nlohmann::json(*s.random_seed) : nlohmann::json()},
                         {"settings", s.settings.string()},
                         {"problem", s.problem},
                         {"has_masks", s.has_masks},
                         {"min_interaction_area", s.min_interaction_area},
                         {"depth_threshold", s.depth_threshold}});
  }
  nlohmann::json variants = nlohmann::json::array();
  for (const Variant& v : plan.variants) {
    nlohmann::json entry = {{"mode", v.mode}};
    if (v.min_interaction_area) entry["min_interaction_area"] = *v.min_interaction_area;
    if (v.depth_threshold) entry["depth_threshold"] = *v.depth_threshold;
    variants.push_back(entry);
  }
  nlohmann::json runs = nlohmann::json::array();
  for (const RunSpec& r : plan.runs) {
    runs.push_back({{"id", r.id}, {"sequence", r.sequence}, {"variant", r.variant}, {"run", r.run}});
  }
  return {{"binary", plan.binary.string()},
          {"folder", plan.folder.string()},
          {"options",
           {{"modes", o.modes},
            {"runs", o.runs},
            {"sweep_runs", o.sweep_runs},
            {"area_sweep", o.area_sweep},
            {"depth_sweep", o.depth_sweep},
            {"frames", o.frames},
            {"synth_frames", o.synth_frames},
            {"synth_frame_step", o.synth_frame_step},
            {"random_duration", o.random_duration},
            {"textures", o.textures.string()},
            {"deterministic", o.deterministic},
            {"realtime", o.realtime},
            {"pace", o.pace},
            {"detector_latency_ms", o.detector_latency_ms},
            {"dense", o.dense},
            {"model", o.model.string()},
            {"snapshots", o.snapshots},
            {"timeout_seconds", o.timeout_seconds}}},
          {"sequences", sequences},
          {"variants", variants},
          {"runs", runs}};
}

Plan PlanFromJson(const nlohmann::json& json, const fs::path& file) {
  try {
    Plan plan;
    const nlohmann::json& o = json.at("options");
    plan.options.modes = o.at("modes").get<std::vector<std::string>>();
    plan.options.runs = o.at("runs").get<std::size_t>();
    plan.options.sweep_runs = o.at("sweep_runs").get<std::size_t>();
    plan.options.area_sweep = o.at("area_sweep").get<std::vector<double>>();
    plan.options.depth_sweep = o.at("depth_sweep").get<std::vector<double>>();
    plan.options.frames = o.at("frames").get<std::size_t>();
    plan.options.synth_frames = o.at("synth_frames").get<std::size_t>();
    plan.options.synth_frame_step = o.at("synth_frame_step").get<int>();
    // Benches planned before random sequences existed rendered none.
    plan.options.random_duration = o.value("random_duration", 0.0);
    plan.options.textures = o.value("textures", std::string());
    plan.options.deterministic = o.at("deterministic").get<bool>();
    // Benches planned before the real-time mode existed ran synchronously.
    plan.options.realtime = o.value("realtime", false);
    plan.options.pace = o.value("pace", false);
    plan.options.detector_latency_ms = o.value("detector_latency_ms", 0.0);
    // Benches planned before dense maps existed made none.
    plan.options.dense = o.value("dense", false);
    plan.options.model = o.at("model").get<std::string>();
    plan.options.snapshots = o.at("snapshots").get<std::size_t>();
    plan.options.timeout_seconds = o.at("timeout_seconds").get<double>();
    plan.binary = json.at("binary").get<std::string>();
    plan.folder = json.at("folder").get<std::string>();
    for (const nlohmann::json& s : json.at("sequences")) {
      BenchSequence& sequence = plan.sequences.emplace_back();
      sequence.name = s.at("name").get<std::string>();
      sequence.path = s.at("path").get<std::string>();
      sequence.scenario = s.at("scenario").get<std::string>();
      if (s.contains("random_seed") && !s["random_seed"].is_null()) {
        sequence.random_seed = s["random_seed"].get<std::uint64_t>();
      }
      sequence.settings = s.at("settings").get<std::string>();
      sequence.problem = s.at("problem").get<std::string>();
      sequence.has_masks = s.at("has_masks").get<bool>();
      sequence.min_interaction_area = s.at("min_interaction_area").get<double>();
      sequence.depth_threshold = s.at("depth_threshold").get<double>();
    }
    for (const nlohmann::json& v : json.at("variants")) {
      Variant variant = Variant::Plain(v.at("mode").get<std::string>());
      if (v.contains("min_interaction_area")) variant.min_interaction_area = v["min_interaction_area"].get<double>();
      if (v.contains("depth_threshold")) variant.depth_threshold = v["depth_threshold"].get<double>();
      plan.variants.push_back(variant);
    }
    for (const nlohmann::json& r : json.at("runs")) {
      RunSpec spec{.id = r.at("id").get<std::string>(),
                   .sequence = r.at("sequence").get<std::size_t>(),
                   .variant = r.at("variant").get<std::size_t>(),
                   .run = r.at("run").get<std::size_t>()};
      if (spec.sequence >= plan.sequences.size() || spec.variant >= plan.variants.size()) {
        throw core::InputError::InFile(file, fmt::format("run {} refers to a sequence or variant not listed", spec.id));
      }
      plan.runs.push_back(spec);
    }
    return plan;
  } catch (const nlohmann::json::exception& e) {
    throw core::InputError::InFile(file, fmt::format("not a bench plan: {}", e.what()));
  }
}

std::string ShellCommand(const std::vector<std::string>& arguments) {
  std::string line;
  for (const std::string& argument : arguments) {
    if (!line.empty()) line += ' ';
    const bool plain = !argument.empty() && argument.find_first_not_of(
                                                "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789"
                                                "_-+=/.,:@%") == std::string::npos;
    if (plain) {
      line += argument;
      continue;
    }
    line += '\'';
    for (const char c : argument) line += c == '\'' ? std::string("'\\''") : std::string(1, c);
    line += '\'';
  }
  return line;
}

}  // namespace hoidslam::bench
