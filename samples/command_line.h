// Argument handling shared by the command-line tools, on pcl::console as PCL's own
// tools do, with what those leave to each tool: unknown options and flags without a
// value are errors, and every error names the flag.
#pragma once

#include <pcl/console/parse.h>
#include <pcl/console/print.h>

#include <array>
#include <string>
#include <vector>

namespace meshless_tools {

/** A flag a tool knows; one with a value takes the next argument. */
struct Flag
{
  const char* name;
  bool takes_value;
};

/** The command line checked against the flags a tool knows. A later copy of a flag
  * overrides an earlier one (wrapper scripts append their overrides); the values are
  * then read with pcl::console::parse_argument. */
class CommandLine
{
public:
  CommandLine (int argc, const char* const* argv, const std::vector<Flag>& flags);

  /** An empty string, or what is wrong (an unknown option, a missing value, a value
    * of the wrong kind), naming the flag. */
  const std::string&
  error () const
  {
    return error_;
  }

  /** The arguments that are neither flags nor their values, in order. */
  const std::vector<std::string>&
  positional () const
  {
    return positional_;
  }

  /** True when the flag was given (pcl::console::find_switch). */
  bool
  has (const char* flag) const;

  /** Reads the flag's value into `value` when the flag was given; false (and
    * error ()) when the value is not a T. T: int, double, std::string. */
  template <typename T>
  bool
  read (const char* flag, T& value);

  /** Reads "X,Y,Z" (pcl::console::parse_3x_arguments) when the flag was given; false
    * (and error ()) when it is not three numbers. */
  bool
  read3 (const char* flag, std::array<double, 3>& value);

  /** The index in `choices` of the flag's value, left as it is when the flag is
    * absent; false (and error ()) when the value is none of them. */
  bool
  choose (const char* flag, const std::vector<std::string>& choices, int& chosen);

  /** Sets error () to "FLAG <rule> (got 'VALUE')" and returns false. */
  bool
  reject (const char* flag, const std::string& rule);

private:
  std::string
  raw (const char* flag) const;

  std::vector<std::string> kept_; // program, then the last copy of each flag given
  std::vector<const char*> argv_; // kept_ as pcl::console reads it
  std::vector<std::string> positional_;
  std::string error_;
};

/** Silences PCL's log while it lives: the tools say each failure themselves, in one
  * line naming the flag or the file, where PCL's log would repeat it naming C++
  * setters. */
class QuietPclLog
{
public:
  QuietPclLog () : level_ (pcl::console::getVerbosityLevel ())
  {
    pcl::console::setVerbosityLevel (pcl::console::L_ALWAYS);
  }
  ~QuietPclLog () { pcl::console::setVerbosityLevel (level_); }
  QuietPclLog (const QuietPclLog&) = delete;
  QuietPclLog&
  operator= (const QuietPclLog&) = delete;

private:
  pcl::console::VERBOSITY_LEVEL level_;
};

/** "TOOL: REASON" as one line on stderr (pcl::console::print_error); returns 1, the
  * tools' exit status for every failure. */
int
fail (const char* tool, const std::string& reason);

} // namespace meshless_tools
