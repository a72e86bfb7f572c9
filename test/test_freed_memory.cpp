// Freed memory given back to the operating system between stages.
#include <pcl/surface/meshless/freed_memory.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <vector>

namespace {

/** The process's resident set in kB (Linux), or -1. */
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
  if (!pcl::meshless::releaseFreedMemory () || residentKilobytes () < 0)
    GTEST_SKIP () << "not glibc on Linux";
  // 200 MB in blocks small enough for the heap, every 64th kept: the heap cannot
  // shrink from its top, and free () alone leaves the rest resident.
  constexpr std::size_t blocks = 200000, size = 1000;
  std::vector<std::unique_ptr<char[]>> kept, freed;
  for (std::size_t k = 0; k < blocks; ++k) {
    auto block = std::make_unique<char[]> (size);
    for (std::size_t i = 0; i < size; i += 256)
      block[i] = static_cast<char> (k);
    (k % 64 == 63 ? kept : freed).push_back (std::move (block));
  }
  freed.clear ();
  const long before = residentKilobytes ();
  ASSERT_TRUE (pcl::meshless::releaseFreedMemory ());
  const long after = residentKilobytes ();
  EXPECT_LT (after, before - 100 * 1024) << before << " kB -> " << after << " kB";
  EXPECT_EQ (kept.size (), blocks / 64);
}
