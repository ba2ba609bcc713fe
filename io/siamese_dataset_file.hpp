// Seed 003 (TTCSN) pair data set files (HDF5), readable with h5py:
//
//   /  attrs: format = "trackassoc-seed003-dataset", schema_version = 1, generator (JSON options)
//   /radar1/x, y, t (float64, one entry per converted plot), offset (int64, tracks+1: track k is
//          plots [offset[k], offset[k+1])), target (int32, tracks: the target id of each track)
//   /radar2/  the same for radar 2
//   /pairs/train/left (int32, a /radar1 track), right (int32, a /radar2 track), label (uint8,
//          1 = same target), kind (uint8: 0 positive, 1 random negative, 2 close negative)
//   /pairs/test/  the same
//
// Built on io/hdf5_wrapper.hpp. Reading (in a forked child first, as read_track_file) checks format,
// version, shapes, dtypes, value ranges, finite values, offsets, time order and pair indices.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "kernels/learning/siamese.hpp"

namespace trackassoc {

enum class PairKind : uint8_t { kPositive = 0, kRandomNegative = 1, kCloseNegative = 2 };

struct Seed003Dataset {
  TrackSequences radar1, radar2;
  std::vector<int32_t> target1, target2;  // target id per track
  PairSet train, test;
  std::vector<uint8_t> train_kind, test_kind;  // PairKind per pair
  std::string generator_json = "{}";
};

void write_seed003_dataset(const std::string& path, const Seed003Dataset& data);
Seed003Dataset read_seed003_dataset(const std::string& path);

}  // namespace trackassoc
