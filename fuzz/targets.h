#pragma once
// The fuzz targets, one per parser users feed files to. Each is a libFuzzer program in the fuzz build
// (libfuzzer_main.cc) and is replayed over its corpus and regressions by the ordinary test suite
// (replay_test.cc). docs/fuzzing.md describes them.

#include <span>
#include <string_view>

#include "fuzz/fuzz_target.h"

namespace hoidslam::fuzz {

struct Target {
  std::string_view name;  // also the folder of its inputs: fuzz/corpus/<name>, fuzz/regressions/<name>
  void (*run)(Bytes input);
};

void FuzzSettings(Bytes input);      // a settings YAML file: io::LoadSettings
void FuzzTumLists(Bytes input);      // rgb.txt %% depth.txt %% groundtruth.txt: io::RgbdSequence::OpenTum
void FuzzAssociations(Bytes input);  // an associations file: io::RgbdSequence::OpenTum with `associations`
void FuzzTrajectory(Bytes input);    // a TUM trajectory: io::ReadTumTrajectory
void FuzzDetections(Bytes input);    // a detections file: io::DetectionsFile::Read
void FuzzScenario(Bytes input);      // a scenario JSON file: synth::ParseScenario
void FuzzVocabulary(Bytes input);    // a vocabulary file: bow::Vocabulary::Load
void FuzzMapFile(Bytes input);       // a map file: slam::DecodeMap, then slam::RebuildMap
void FuzzPly(Bytes input);           // a PLY file: io::ReadPly, io::ReadPlyMesh, io::ReadVoxelCentresPly

std::span<const Target> Targets();

// The target of that name; throws std::invalid_argument for an unknown one.
const Target& FindTarget(std::string_view name);

}  // namespace hoidslam::fuzz
