// The process-wide memory budget (docs/design.md §2 and §7: no input may exhaust memory). Every
// reader, generator and pipeline stage works out how many bytes a request needs (a file's dataset
// shapes, a scenario's targets × steps, a header's n1·n2·n3, the aligned tracks' spans) and checks
// it BEFORE it allocates, so that a file or an option asking for more than the machine can give is
// refused with an InputError naming the size, the budget and how to raise it, instead of
// std::bad_alloc after gigabytes. The CLI sets the budget with the global option --memory-budget MIB.
//
// What counts (issue 31): the WORK's memory, i.e. the process's resident set above its baseline,
// plus the request. The baseline is the resident set when the budget was set (the CLI sets it
// before it reads anything: the code, the shared libraries, the C++ runtime, a sanitizer's shadow
// memory; ~15 MiB in Release), or at the first check when it never was. Under AddressSanitizer,
// whose shadow memory and quarantine of freed blocks (up to 256 MiB) grow with the work but are
// not the work's, only the stages' counts are checked (work_resident_bytes() is 0). A
// check passes when max(what the stages count they hold, resident − baseline) + request ≤ budget
// (require_memory_beside_held), so peak resident ≤ baseline + budget. Why the resident set and
// not only the requests: it is what the machine charges (the OOM killer, a cgroup, /usr/bin/time),
// and a sum of requests missed the allocator's slack, freed memory it keeps, libraries' caches and
// the leftovers of earlier stages (recorded_30k at a 400 MiB budget peaked at 440 MiB with every
// request within). Why the request is added and not read from it: pages count only once touched,
// so an allocation shows in the resident set only as it is filled. Its limits: freed memory the
// allocator keeps still counts (conservative: a stage may be refused that would have reused it);
// a stage whose size is known only as it runs counts its buffers on an AllocationGauge
// (kernels/core/allocation_gauge.hpp) by capacity, beside the resident set at its start
// (require_memory_beside), as the candidate search does (its per-thread scratch too); small
// allocations (messages, a solver's per-component scratch) are not. Default: half of the physical
// or cgroup memory.
#pragma once

#include <cstddef>
#include <string>

namespace trackassoc {

// The default budget: half of the physical memory (the smaller of sysconf's physical pages and a
// cgroup v2 memory.max limit, when there is one); 4 GiB when neither can be read.
std::size_t default_memory_budget_bytes();

// The current budget [bytes]; default_memory_budget_bytes() until set_memory_budget_bytes.
std::size_t memory_budget_bytes();
// Throws InputError when `bytes` is 0.
void set_memory_budget_bytes(std::size_t bytes);
// True once set_memory_budget_bytes was called (the user chose a budget).
bool memory_budget_was_set();

// `count` × `size` [bytes], saturating at SIZE_MAX instead of wrapping.
std::size_t bytes_of(double count, std::size_t size);

// Throws InputError "<what> needs N MiB, more than the memory budget of B MiB (raise it with
// --memory-budget MIB, ...)" when `bytes` > memory_budget_bytes().
void require_memory(std::size_t bytes, const std::string& what);

// The process's resident set now [bytes] (/proc/self/statm; 0 where it cannot be read).
std::size_t resident_bytes();
// What the work holds: the resident set above the program's own, measured when the budget was set
// (the CLI sets it before it reads anything; the code, the libraries, a sanitizer's shadow memory
// are not the work's), or at the first call when it never was.
std::size_t work_resident_bytes();

// require_memory(held + bytes) with held = max(`held`, work_resident_bytes()): what the stages
// count they hold, or what the process really holds when that is more (the input, the allocator's
// slack, another stage's leftovers), so that the budget bounds the process, not only each request.
// The message names both: "<what> needs N MiB beside the H MiB held (the input and the stages
// before), more than the memory budget of B MiB; ...".
void require_memory_beside_held(double held, double bytes, const std::string& what);

// max(`held`, work_resident_bytes()): what a stage starts beside.
double held_or_resident(double held);
// The same check and message as require_memory_beside_held with `held` as given (the resident set
// is not read again): for a stage that counts its own growth on top of what it started beside
// (kernels/core/allocation_gauge.hpp), whose buffers are by then in the resident set too.
void require_memory_beside(double held, double bytes, const std::string& what);

// True in a build with AddressSanitizer, where the resident set is not the work's (above).
bool address_sanitizer_build();

// "1.5 GiB", "12 MiB", "640 bytes": a size for messages.
std::string size_text(std::size_t bytes);

}  // namespace trackassoc
