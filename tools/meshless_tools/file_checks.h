// Checks of an input file's structure before PCL's readers see it. Those readers
// trust the header: a count larger than the data, a header line with missing values
// or an ASCII line with too few numbers makes them read past their buffers, throw
// through their callers or allocate what the header claims. A file refused here ends
// in a one-line cause instead.
#pragma once

#include <string>

namespace meshless_tools {

/** Checks a PCD header (FIELDS, SIZE, TYPE and COUNT agree; WIDTH * HEIGHT is
  * POINTS; DATA is ascii, binary or binary_compressed) and that the data it announces
  * is in the file: POINTS lines of the right number of values for ascii, POINTS times
  * the point size for binary, the compressed block and its uncompressed size for
  * binary_compressed.
  * \return an empty string, or the cause (without the path) */
std::string
checkPcdFile (const std::string& path);

/** Checks a PLY header (format, elements, properties and their types) and that its
  * elements are in the file: every list's length within its line (ascii) or the
  * file (binary), before PCL's reader allocates what the counts claim.
  * \return an empty string, or the cause (without the path) */
std::string
checkPlyFile (const std::string& path);

} // namespace meshless_tools
