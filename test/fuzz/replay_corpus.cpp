/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
// Runs a fuzz target's checks on every file of its committed corpus without
// libFuzzer: the seeds and the fuzzer's findings (finding-*) become a regression
// test of the ordinary builds, scripts/test and scripts/sanitize included.
//   test_fuzz_corpus DIRECTORY_OR_FILE...
// A broken promise aborts (as in the fuzzer), naming the input first.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerInitialize (int* argc, char*** argv);
extern "C" int LLVMFuzzerTestOneInput (const std::uint8_t* data, std::size_t size);

int
main (int argc, char** argv)
{
  std::vector<std::filesystem::path> inputs;
  for (int i = 1; i < argc; ++i) {
    if (std::filesystem::is_directory (argv[i])) {
      for (const auto& entry : std::filesystem::directory_iterator (argv[i]))
        if (entry.is_regular_file ())
          inputs.push_back (entry.path ());
    }
    else
      inputs.emplace_back (argv[i]);
  }
  std::sort (inputs.begin (), inputs.end ());
  if (inputs.empty ()) {
    std::fprintf (stderr, "usage: %s DIRECTORY_OR_FILE... (no input found)\n", argv[0]);
    return 2;
  }
  LLVMFuzzerInitialize (&argc, &argv);
  for (const auto& path : inputs) {
    std::ifstream in (path, std::ios::binary);
    if (!in) {
      std::fprintf (stderr, "cannot read %s\n", path.c_str ());
      return 1;
    }
    const std::vector<char> bytes ((std::istreambuf_iterator<char> (in)),
                                   std::istreambuf_iterator<char> ());
    std::fprintf (stderr, "%s\n", path.filename ().c_str ());
    LLVMFuzzerTestOneInput (reinterpret_cast<const std::uint8_t*> (bytes.data ()),
                            bytes.size ());
  }
  std::printf ("%zu inputs kept every promise\n", inputs.size ());
  return 0;
}
