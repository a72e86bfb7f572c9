// Freed memory given back to the operating system between stages.
#include "common/freed_memory.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <vector>

namespace {

/** The process's resident set in kB (Linux), or -1 where /proc is not there. */
long
residentKilobytes ()
{
  std::FILE* status = std::fopen ("/proc/self/status", "r");
  if (!status)
    return -1;
  char line[256];
  long kilobytes = -1;
  while (std::fgets (line, sizeof line, status))
    if (std::sscanf (line, "VmRSS: %ld kB", &kilobytes) == 1)
      break;
  std::fclose (status);
  return kilobytes;
}

} // namespace

TEST (FreedMemory, ReturnsFreedHeapPagesToTheSystem)
{
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP () << "AddressSanitizer has an allocator of its own";
#endif
  if (residentKilobytes () < 0)
    GTEST_SKIP () << "no /proc/self/status to read the resident set from";
  if (!pcl::meshless::releaseFreedMemory ())
    GTEST_SKIP () << "the C library offers no way to return freed memory";

  // 200 MB in blocks small enough for the heap, every 64th kept: the heap cannot
  // shrink from its top, so free () alone leaves the freed blocks' pages resident.
  constexpr std::size_t blocks = 200000, size = 1000, kept_every = 64;
  const long at_start = residentKilobytes ();
  std::vector<std::unique_ptr<char[]>> kept, freed;
  for (std::size_t k = 0; k < blocks; ++k) {
    auto block = std::make_unique<char[]> (size); // zeroed: every page touched
    block[0] = static_cast<char> (k);
    (k % kept_every == kept_every - 1 ? kept : freed).push_back (std::move (block));
  }
  const long allocated = residentKilobytes ();
  const long freed_kilobytes = static_cast<long> (freed.size () * size / 1024);
  ASSERT_GT (allocated - at_start, freed_kilobytes * 9 / 10)
      << "the blocks should be resident: " << at_start << " kB -> " << allocated << " kB";

  freed.clear ();
  const long after_free = residentKilobytes ();
  if (allocated - after_free > freed_kilobytes / 4)
    GTEST_SKIP () << "free () alone returned the pages (" << allocated << " kB -> "
                  << after_free << " kB): nothing left to measure";

  ASSERT_TRUE (pcl::meshless::releaseFreedMemory ());
  const long after_release = residentKilobytes ();
  ::testing::Test::RecordProperty ("freed_kB", static_cast<int> (freed_kilobytes));
  ::testing::Test::RecordProperty ("resident_after_free_kB", static_cast<int> (after_free));
  ::testing::Test::RecordProperty ("resident_after_release_kB", static_cast<int> (after_release));
  // Whole free pages between the kept blocks go back: 15 of every 16 here. A
  // quarter of slack for the allocator's bookkeeping and the rest of the process.
  EXPECT_GT (after_free - after_release, freed_kilobytes * 3 / 4)
      << after_free << " kB -> " << after_release << " kB after releasing "
      << freed_kilobytes << " kB of freed blocks";

  // The blocks still in use are untouched.
  for (std::size_t i = 0; i < kept.size (); ++i)
    ASSERT_EQ (kept[i][0], static_cast<char> (i * kept_every + kept_every - 1)) << "block " << i;
}
