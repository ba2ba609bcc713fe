// Runs a check in a child process, so that a crash or a hang inside a third-party library becomes
// an InputError instead of taking the program down (docs/design.md §2: no input may crash or hang it).
//
// Why: libhdf5 1.10 has known bugs on damaged files; libFuzzer (tests/fuzz/fuzz_track_file) found
// hangs and heap overflows inside the library's global-heap and object-header decoding. The engine
// cannot fix the library, so read_track_file first reads the file in a forked child: if the child
// crashes, is killed, or does not finish in time, the parent reports the file as corrupt without
// ever touching it with HDF5 itself; if the child finds an InputError, the parent throws the same
// message; only a file the child read completely is read again in process.
#pragma once

#include <functional>
#include <string>

namespace trackassoc {

// Calls `check` in a forked child. Throws InputError: with the child's message when `check`
// threw InputError; "<subject>: ... crashed ..." when the child died; "<subject>: ... did not
// finish within T s ..." after `timeout_s`. Returns normally when `check` returned. When fork()
// is unavailable it calls `check` in process. The child is killed with its parent
// (PR_SET_PDEATHSIG), so a parent killed by SIGKILL leaves no reader spinning.
void run_isolated(const std::string& subject, const std::function<void()>& check, double timeout_s);

// True inside the child of run_isolated. The child is there to exercise the library; the checks
// of values that are pure computation on what was read (io/track_validation.hpp, check_tracks' rows)
// run once, in the parent, on its own read of the same file. A forked child also never starts a
// oneTBB task arena its parent may already hold.
bool in_isolated_child();

// The child's time limit for reading `path`: 10 s plus 1 s per 5 MB of file. A sound file reads
// far faster: the 70 MB recorded_10k simulation is read twice (child, then parent) in 1.5 s on a
// loaded 2-core machine, against its limit of 24 s; a damaged 33 KB file is given up after 10 s.
double isolated_read_timeout(const std::string& path);

// The pattern of read_track_file for any reader: `read(path)` first in a forked child (time limit
// isolated_read_timeout), then, when the child finished, in process.
template <class Read>
auto read_isolated(const std::string& path, Read read) -> decltype(read(path)) {
  run_isolated(
      path, [&] { read(path); }, isolated_read_timeout(path));
  return read(path);
}

}  // namespace trackassoc
