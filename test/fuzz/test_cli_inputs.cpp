/*
 * Software License Agreement (BSD License)
 *  pcl_spherical_meshless - see LICENSE.
 */
// Broken input files through the reconstruction CLI (MESHLESS_CLI): the seeds in
// corpus_readers/ (one small valid file per format and encoding) cut short, with
// lying headers, followed by junk, and random bytes under each extension. Every run
// ends in an exit status of 0 or 1, never a signal; a failure is one line on stderr,
// and a file that cannot be read is named in it.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct Variant
{
  std::string name;
  std::string bytes;
  bool must_fail = true; // false: it may still be a readable cloud
};

std::string
readFile (const fs::path& path)
{
  std::ifstream in (path, std::ios::binary);
  return std::string ((std::istreambuf_iterator<char> (in)), std::istreambuf_iterator<char> ());
}

std::string
randomBytes (std::mt19937& random, std::size_t size)
{
  std::string bytes (size, '\0');
  for (auto& byte : bytes)
    byte = static_cast<char> (random () & 0xff);
  return bytes;
}

/** `bytes` with the first `from` replaced by `to`; empty when `from` is not there. */
std::string
lie (const std::string& bytes, const std::string& from, const std::string& to)
{
  const auto at = bytes.find (from);
  return at == std::string::npos ? "" : std::string (bytes).replace (at, from.size (), to);
}

struct Lie
{
  std::string from, to;
  bool must_fail = true; // false: the data may happen to fit the lie
};

/** Header lines that claim more than the file holds, or claim it wrongly. */
const std::vector<Lie> kLies = {
    {"POINTS 12", "POINTS 1200000000"},
    {"WIDTH 12\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 12",
     "WIDTH 3000000\nHEIGHT 4000\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 12000000000"},
    {"WIDTH 12\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 12",
     "WIDTH 12000000\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 12000000"},
    {"SIZE 4 4 4", "SIZE 4 4"},
    {"TYPE F F F", "TYPE F F U7"},
    {"COUNT 1 1 1", "COUNT 1 1 0"},
    {"FIELDS x y z", "FIELDS x y z w"},
    {"DATA binary_compressed", "DATA"},
    {"DATA binary\n", "DATA ascii\n"},
    {"DATA ascii\n", "DATA binary\n", false},
    {"\nVIEWPOINT", "\nVIEWPOINT 1 2"},
    {"element vertex 12", "element vertex 4000000000"},
    {"element face 4", "element face 40000000"},
    {"property list uchar int", "property list uint int", false},
    {"format ascii", "format binary_little_endian", false},
    {"format binary_little_endian", "format ascii"},
    {"end_header", "end_headr"},
    {"3 0 1 2", "255 0 1 2"},
    {"property float x", "property float128 x"},
    {"property float x", "property\n0. float x"}, // a property line with no type
};

std::vector<Variant>
variantsOf (const fs::path& seed)
{
  const std::string bytes = readFile (seed);
  const std::string ext = seed.extension ().string ();
  std::vector<Variant> variants;
  for (const double fraction : {0.0, 0.1, 0.3, 0.6, 0.9}) {
    const auto length = static_cast<std::size_t> (fraction * bytes.size ());
    // A .xyz cut between lines is a smaller cloud; everything else announces more.
    variants.push_back ({"cut" + std::to_string (length), bytes.substr (0, length),
                         ext != ".xyz" || length == 0});
  }
  // The last two bytes: a value short in binary data and in a PLY's last list.
  const bool ascii = seed.stem ().string ().find ("ascii") != std::string::npos;
  variants.push_back ({"cut-end", bytes.substr (0, bytes.size () - 2),
                       ext == ".ply" || (ext == ".pcd" && !ascii)});
  for (std::size_t i = 0; i < kLies.size (); ++i) {
    std::string lied = lie (bytes, kLies[i].from, kLies[i].to);
    if (!lied.empty ())
      variants.push_back ({"lie" + std::to_string (i), lied, kLies[i].must_fail});
  }
  std::mt19937 random (static_cast<unsigned> (bytes.size ()));
  variants.push_back ({"junk-after", bytes + randomBytes (random, 64), false});
  if (ext == ".xyz") {
    variants.push_back ({"word", bytes + "1 2 three\n", true});
    variants.push_back ({"two-numbers", "1 2\n" + bytes, true});
  }
  return variants;
}

struct CliRun
{
  int status = -1; // the exit status, or 128 + the signal
  std::vector<std::string> err;
};

CliRun
runCli (const fs::path& input, const fs::path& output)
{
  const fs::path err = output.string () + ".err";
  // exec: a signal that kills the CLI is the shell's child's, not hidden in its status.
  const std::string command = std::string ("exec \"") + MESHLESS_CLI + "\" \"" +
                              input.string () + "\" \"" + output.string () +
                              "\" >/dev/null 2>\"" + err.string () + "\"";
  CliRun run;
  const int raw = std::system (command.c_str ());
  run.status = WIFEXITED (raw) ? WEXITSTATUS (raw) : 128 + WTERMSIG (raw);
  std::istringstream lines (readFile (err));
  for (std::string line; std::getline (lines, line);)
    run.err.push_back (line);
  return run;
}

void
expectCleanEnd (const fs::path& input, const fs::path& output, bool must_fail)
{
  SCOPED_TRACE (input.string ());
  const CliRun run = runCli (input, output);
  ASSERT_TRUE (run.status == 0 || run.status == 1) << "status " << run.status;
  if (must_fail)
    EXPECT_EQ (run.status, 1);
  if (run.status == 0)
    return;
  ASSERT_EQ (run.err.size (), 1u) << "one line on stderr";
  EXPECT_EQ (run.err[0].rfind ("pcl_spherical_meshless_surface: ", 0), 0u) << run.err[0];
  if (must_fail)
    EXPECT_NE (run.err[0].find (input.string ()), std::string::npos)
        << "the file is named: " << run.err[0];
}

class CliInputs : public ::testing::Test
{
protected:
  void
  SetUp () override
  {
    dir_ = fs::temp_directory_path () / ("cli_inputs_" + std::to_string (::getpid ()));
    fs::create_directories (dir_);
  }
  void
  TearDown () override
  {
    fs::remove_all (dir_);
  }

  fs::path
  write (const std::string& name, const std::string& bytes) const
  {
    const fs::path path = dir_ / name;
    std::ofstream (path, std::ios::binary) << bytes;
    return path;
  }

  fs::path dir_;
};

} // namespace

TEST_F (CliInputs, SeedsAreReadable)
{
  std::size_t seeds = 0;
  for (const auto& entry : fs::directory_iterator (MESHLESS_READERS_CORPUS)) {
    ++seeds;
    SCOPED_TRACE (entry.path ().string ());
    const CliRun run = runCli (entry.path (), dir_ / "out.ply");
    // Twelve points on a sphere: a mesh, so the variants below start from a good file.
    EXPECT_EQ (run.status, 0) << (run.err.empty () ? "" : run.err.back ());
  }
  EXPECT_GE (seeds, 7u);
}

TEST_F (CliInputs, CutLyingAndJunkFilesEndInOneLine)
{
  for (const auto& entry : fs::directory_iterator (MESHLESS_READERS_CORPUS))
    for (const Variant& variant : variantsOf (entry.path ())) {
      const std::string name = entry.path ().stem ().string () + "-" + variant.name +
                               entry.path ().extension ().string ();
      expectCleanEnd (write (name, variant.bytes), dir_ / "out.ply", variant.must_fail);
    }
}

TEST_F (CliInputs, RandomBytesUnderEachExtensionEndInOneLine)
{
  std::mt19937 random (7);
  for (const std::string ext : {".pcd", ".ply", ".xyz"})
    for (const std::size_t size : {1, 16, 300, 4096}) {
      const std::string name = "random" + std::to_string (size) + ext;
      expectCleanEnd (write (name, randomBytes (random, size)), dir_ / "out.ply", true);
    }
  // Random bytes after a plausible first line.
  expectCleanEnd (write ("ply-then-random.ply", "ply\n" + randomBytes (random, 500)),
                  dir_ / "out.ply", true);
  expectCleanEnd (write ("fields-then-random.pcd", "FIELDS x y z\n" + randomBytes (random, 500)),
                  dir_ / "out.ply", true);
}

/** A header of twelve octahedron-and-cube points with `extra` vertex properties, each
  * row carrying `values` after x y z. */
std::string
plyWithVertexProperties (const std::string& extra, const std::string& values)
{
  std::string ply = "ply\nformat ascii 1.0\nelement vertex 12\nproperty float x\n"
                    "property float y\nproperty float z\n" +
                    extra + "end_header\n";
  const char* rows[] = {"1 0 0", "-1 0 0", "0 1 0", "0 -1 0", "0 0 1", "0 0 -1",
                        "0.6 0.6 0.6", "-0.6 0.6 0.6", "0.6 -0.6 0.6", "0.6 0.6 -0.6",
                        "-0.6 -0.6 0.6", "-0.6 -0.6 -0.6"};
  for (const char* row : rows)
    ply += std::string (row) + " " + values + "\n";
  return ply;
}

TEST_F (CliInputs, LayoutsPclWouldMisreadAreRefused)
{
  // PCL's PCD header parser reads on after DATA while lines start with a keyword:
  // binary data that begins with one would redefine the fields.
  std::string data = "FIELDS y\n";
  data.resize (12 * 12, '\x01');
  expectCleanEnd (write ("data-like-header.pcd",
                         "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
                         "WIDTH 12\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 12\nDATA binary\n" +
                             data + "tail\n"),
                  dir_ / "out.ply", true);
  // PCL's reader sizes a vertex list from the first vertex and writes packed colours
  // when blue arrives: these layouts would read past its buffer or read wrongly.
  expectCleanEnd (write ("vertex-list.ply", plyWithVertexProperties (
                                                "property list uchar float v\n", "2 1 2")),
                  dir_ / "out.ply", true);
  expectCleanEnd (write ("blue-alone.ply",
                         plyWithVertexProperties ("property uchar blue\n", "7")),
                  dir_ / "out.ply", true);
  expectCleanEnd (write ("alpha-alone.ply",
                         plyWithVertexProperties ("property uchar alpha\n", "7")),
                  dir_ / "out.ply", true);
  expectCleanEnd (write ("vertex-twice.ply",
                         "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                         "element vertex 1\nproperty float y\nend_header\n1\n2\n"),
                  dir_ / "out.ply", true);
  // The layouts PCL reads: colours in order, with alpha after blue.
  const fs::path coloured = write (
      "coloured.ply", plyWithVertexProperties ("property uchar red\nproperty uchar green\n"
                                               "property uchar blue\nproperty uchar alpha\n",
                                               "10 20 30 255"));
  const CliRun run = runCli (coloured, dir_ / "out.ply");
  EXPECT_EQ (run.status, 0) << (run.err.empty () ? "" : run.err.back ());
}
