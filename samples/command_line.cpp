#include "command_line.h"

#include <algorithm>
#include <map>
#include <sstream>

namespace meshless_tools {

namespace {

template <typename T>
const char*
kindOf ();

template <>
const char*
kindOf<int> ()
{
  return "a whole number";
}

template <>
const char*
kindOf<double> ()
{
  return "a number";
}

template <>
const char*
kindOf<std::string> ()
{
  return "a value";
}

} // namespace

CommandLine::CommandLine (int argc, const char* const* argv, const std::vector<Flag>& flags)
{
  const auto known = [&flags] (const std::string& arg) {
    return std::find_if (flags.begin (), flags.end (),
                         [&arg] (const Flag& f) { return arg == f.name; });
  };
  std::map<std::string, std::string> given; // flag -> its last value
  for (int i = 1; i < argc && error_.empty (); ++i) {
    const std::string arg = argv[i];
    const auto flag = known (arg);
    if (flag == flags.end ()) {
      if (arg.size () > 1 && arg[0] == '-')
        error_ = "unknown option " + arg + " (see -h)";
      else
        positional_.push_back (arg);
    }
    else if (!flag->takes_value)
      given[arg];
    else if (i + 1 >= argc || argv[i + 1][0] == '\0' || known (argv[i + 1]) != flags.end ())
      error_ = arg + " needs a value (see -h)";
    else
      given[arg] = argv[++i];
  }
  kept_.push_back (argc > 0 ? argv[0] : "");
  for (const Flag& flag : flags) {
    const auto found = given.find (flag.name);
    if (found == given.end ())
      continue;
    kept_.push_back (flag.name);
    if (flag.takes_value)
      kept_.push_back (found->second);
  }
  for (const auto& arg : kept_)
    argv_.push_back (arg.c_str ());
}

bool
CommandLine::has (const char* flag) const
{
  return pcl::console::find_switch (static_cast<int> (argv_.size ()), argv_.data (), flag);
}

std::string
CommandLine::raw (const char* flag) const
{
  const int at = pcl::console::find_argument (static_cast<int> (argv_.size ()),
                                              argv_.data (), flag);
  return at >= 0 && at + 1 < static_cast<int> (argv_.size ()) ? kept_[at + 1] : "";
}

template <typename T>
bool
CommandLine::read (const char* flag, T& value)
{
  if (!has (flag))
    return true;
  T parsed{};
  if (pcl::console::parse_argument (static_cast<int> (argv_.size ()), argv_.data (), flag,
                                    parsed) < 0)
    return reject (flag, std::string ("takes ") + kindOf<T> ());
  value = parsed;
  return true;
}

template bool
CommandLine::read<int> (const char*, int&);
template bool
CommandLine::read<double> (const char*, double&);
template bool
CommandLine::read<std::string> (const char*, std::string&);

bool
CommandLine::read3 (const char* flag, std::array<double, 3>& value)
{
  if (!has (flag))
    return true;
  std::array<double, 3> parsed{};
  // parse_3x_arguments reads a missing third value out of its range, and takes
  // words for 0 (atof): three numbers are checked here first.
  std::string text = raw (flag);
  std::replace (text.begin (), text.end (), ',', ' ');
  std::istringstream numbers (text);
  double number = 0.0;
  int count = 0;
  while (numbers >> number)
    ++count;
  if (count != 3 || !numbers.eof () ||
      pcl::console::parse_3x_arguments (static_cast<int> (argv_.size ()), argv_.data (), flag,
                                        parsed[0], parsed[1], parsed[2], false) < 0)
    return reject (flag, "takes X,Y,Z");
  value = parsed;
  return true;
}

bool
CommandLine::choose (const char* flag, const std::vector<std::string>& choices, int& chosen)
{
  if (!has (flag))
    return true;
  const auto found = std::find (choices.begin (), choices.end (), raw (flag));
  if (found != choices.end ()) {
    chosen = static_cast<int> (found - choices.begin ());
    return true;
  }
  std::string rule = "takes ";
  for (std::size_t i = 0; i < choices.size (); ++i)
    rule += (i == 0 ? "" : i + 1 == choices.size () ? " or " : ", ") + choices[i];
  return reject (flag, rule);
}

bool
CommandLine::reject (const char* flag, const std::string& rule)
{
  error_ = std::string (flag) + " " + rule + " (got '" + raw (flag) + "')";
  return false;
}

int
fail (const char* tool, const std::string& reason)
{
  // One line whatever the reason holds: the last line of stderr is the tools' contract.
  std::string line = reason;
  std::replace (line.begin (), line.end (), '\n', ' ');
  pcl::console::print_error ("%s: %s\n", tool, line.c_str ());
  return 1;
}

} // namespace meshless_tools
