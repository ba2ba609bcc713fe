// The Python module's result objects (engine/python/module.cpp): a track file, an association and
// fused tracks, each holding the track file it was computed on, so that fuse, evaluate and write
// need nothing else.
#pragma once

#include <pybind11/pybind11.h>

#include <memory>
#include <mutex>
#include <string>

#include "engine/fusion/track_fuser.hpp"
#include "engine/pipeline/associator.hpp"
#include "io/track_file.hpp"

namespace trackassoc::python {

namespace py = pybind11;

// Debian's libhdf5 is not thread-safe: every read and write of the module holds this (with the GIL
// released, so other Python threads run meanwhile).
std::mutex& hdf5_mutex();

struct PyTrackFile {
  std::shared_ptr<const TrackFile> file;
  std::string source;  // the path it was read from, or "tracks" for arrays
};

struct PyAssociation {
  std::shared_ptr<const TrackFile> input;  // the track set associated
  AssociationOutcome outcome;              // record, unassociated; summary when computed here
  bool computed = false;                   // false: read from a file (the record's attributes only)
};

struct PyFused {
  std::shared_ptr<const TrackFile> input;
  FusedTrackRecord record;
  std::optional<TrackFuserSummary> summary;
};

// The association `rec` of `file` as a result object (unassociated tracks from the record's
// /unassociated rows when stored, else worked out from its tuples).
PyAssociation association_of_file(std::shared_ptr<const TrackFile> file, const AssociationRecord& rec);

void bind_results(py::module_& m);

}  // namespace trackassoc::python
