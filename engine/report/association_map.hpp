// The recording as a map, with what an association made of it (`trackassoc run`, `associate
// --plots`): every local track in the horizontal plane (x, y), coloured by the output target it
// went to (the tuple, or the target number when track segments were joined), the sensor shown by
// the marker at the track's last report; tracks in no tuple of two or more in grey. Where the file
// has truth (engine/pipeline/metrics.hpp's rule): each wrongly joined link of a false tuple is a
// red line between the two tracks (at the middle of their common time, or of the gap between
// them), and each missed target's true path is dashed.
#pragma once

#include <string>

#include "engine/report/canvas.hpp"
#include "engine/report/figure.hpp"
#include "io/track_file.hpp"

namespace trackassoc::report {

inline constexpr int kMapWidth = 1100, kMapHeight = 780;

void draw_association_map(Canvas& canvas, const TrackFile& file, const AssociationRecord& record,
                          const std::string& title);

void write_association_map(const std::string& path, ImageFormat format, const TrackFile& file,
                           const AssociationRecord& record, const std::string& title);

}  // namespace trackassoc::report
