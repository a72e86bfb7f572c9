/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
// libFuzzer target: raw bytes as an input file of each kind the command-line tools
// read (.pcd, .ply and .xyz clouds through meshless_tools::loadCloud, a .ply mesh
// through loadMesh). A file must load or be refused with a cause that names it;
// crashes, sanitizer reports, escaping exceptions and hangs are libFuzzer's.
#include <meshless_tools/cloud_io.h>

#include <pcl/console/print.h>

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

[[noreturn]] void
broken (const char* what, const std::string& path, const std::string& error)
{
  std::fprintf (stderr, "fuzz_readers: %s\n  file %s\n  error '%s'\n", what, path.c_str (),
                error.c_str ());
  std::fflush (stderr);
  std::abort ();
}

/** One file per extension in a directory of this process's own. */
std::string
inputPath (const char* extension)
{
  static const std::filesystem::path dir = [] {
    auto path = std::filesystem::temp_directory_path () /
                ("fuzz_readers_" + std::to_string (::getpid ()));
    std::filesystem::create_directories (path);
    return path;
  }();
  return (dir / (std::string ("input") + extension)).string ();
}

void
checkRefusal (const std::string& path, const std::string& error)
{
  if (!error.empty () && error.find (path) == std::string::npos)
    broken ("a refusal that does not name the file", path, error);
}

} // namespace

extern "C" int
LLVMFuzzerInitialize (int* /*argc*/, char*** /*argv*/)
{
  // The readers' refusals are expected; PCL's log would flood the fuzzer's.
  pcl::console::setVerbosityLevel (pcl::console::L_ALWAYS);
  return 0;
}

extern "C" int
LLVMFuzzerTestOneInput (const std::uint8_t* data, std::size_t size)
{
  for (const char* extension : {".pcd", ".ply", ".xyz"}) {
    const std::string path = inputPath (extension);
    std::ofstream (path, std::ios::binary | std::ios::trunc)
        .write (reinterpret_cast<const char*> (data), static_cast<std::streamsize> (size));
    pcl::PointCloud<pcl::PointXYZ> cloud;
    const std::string error = meshless_tools::loadCloud (path, cloud);
    checkRefusal (path, error);
    // Every point takes at least a byte of the file: more is a count believed.
    if (error.empty () && cloud.size () > size)
      broken ("more points than bytes", path, error);
    if (std::string (extension) == ".ply") {
      pcl::meshless::Points3 vertices;
      pcl::meshless::Triangles triangles;
      checkRefusal (path, meshless_tools::loadMesh (path, vertices, triangles));
    }
  }
  return 0;
}
