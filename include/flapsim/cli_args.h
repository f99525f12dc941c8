// The command-line parser of the tools (evolve, flight_check, sweep, make_creature): one table
// of flags per tool, each bound to the field it sets, with its range. A bad number ("3x"), an
// unknown flag, a missing value or a value out of range is refused naming the flag; --help is
// generated from the table and shows the values the fields hold when it is printed, so the
// defaults shown are those of what runs. ROS-free; no clock.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace flapsim {

/// A closed range [lo, hi], or (lo, hi] if `open_lo`.
struct CliRange {
  double lo = 0.0;
  double hi = 0.0;
  bool open_lo = false;
  bool contains(double x) const { return (open_lo ? x > lo : x >= lo) && x <= hi; }
  std::string text() const;
};

/// Longest value quoted back in an error message (characters).
constexpr std::size_t kMaxQuotedValue = 40;
/// Longest text value (a path, a name): 4096 characters.
constexpr std::size_t kMaxTextValue = 4096;

/// `value` in single quotes, cut to kMaxQuotedValue characters ("..." marks a cut).
std::string quoteValue(const std::string& value);

/// One flag of a table.
struct CliFlag {
  std::vector<std::string> names;     // "--pairs" first, then aliases ("-n")
  std::vector<std::string> metavars;  // one per value; empty: a switch
  std::string help;
  std::string tag;  // free for the tool (evolve marks the flags that define a run "spec")
  std::function<void(const std::vector<std::string>& values)> set;  // throws InputError
  std::function<std::string()> shown;  // the default shown in --help ("" : none)
};

/// What parse() saw: each flag given, in order, with its values as written.
struct CliSeen {
  const CliFlag* flag = nullptr;
  std::vector<std::string> values;
};

/// A table of flags. The setters store into the fields the table was built over; those
/// fields must outlive it.
class CliParser {
 public:
  /// `synopsis`: "usage: tool [options]"; `notes`: text printed after the flags.
  explicit CliParser(std::string synopsis, std::string notes = "");

  CliParser& integer(const std::string& names, const std::string& metavar, int* field,
                     CliRange range, const std::string& help);
  CliParser& real(const std::string& names, const std::string& metavar, double* field,
                  CliRange range, const std::string& help);
  /// A 64-bit unsigned integer (digits only).
  CliParser& seed(const std::string& names, const std::string& metavar, std::uint64_t* field,
                  const std::string& help);
  /// Text of at most kMaxTextValue characters; one of `choices` if they are given.
  CliParser& text(const std::string& names, const std::string& metavar, std::string* field,
                  const std::string& help, const std::vector<std::string>& choices = {});
  /// A switch: sets `*field = value`.
  CliParser& flag(const std::string& names, bool* field, bool value, const std::string& help);
  /// A comma-separated list of 1 to `max_items` numbers, each in `range`.
  CliParser& reals(const std::string& names, const std::string& metavar, std::vector<double>* field,
                   CliRange range, int max_items, const std::string& help);
  CliParser& integers(const std::string& names, const std::string& metavar, std::vector<int>* field,
                      CliRange range, int max_items, const std::string& help);
  /// A comma-separated list of 1 to `max_items` of `choices`.
  CliParser& texts(const std::string& names, const std::string& metavar,
                   std::vector<std::string>* field, const std::vector<std::string>& choices,
                   int max_items, const std::string& help);
  /// Any other flag: `set` gets its values (one per metavar) and throws InputError naming the
  /// flag; `shown` gives the default for --help.
  CliParser& custom(const std::string& names, const std::vector<std::string>& metavars,
                    std::function<void(const std::vector<std::string>&)> set,
                    std::function<std::string()> shown, const std::string& help);
  /// Tags the last flag added.
  CliParser& tag(const std::string& tag);
  /// Sets how --help shows the default of the last flag added.
  CliParser& shows(std::function<std::string()> shown);

  /// Parses `args` (without the program name) into the fields. "--help" and "-h" set help();
  /// roslaunch's `name:=value` arguments are skipped if `skip_remaps`. Throws InputError
  /// naming the flag: unknown, a value missing, not a number, out of range, an empty item of a
  /// list ("a,,b", "a,b,"), or given twice (unless `later_wins`: a resumed run's flags followed
  /// by the command line's).
  std::vector<CliSeen> parse(const std::vector<std::string>& args, bool skip_remaps = false,
                             bool later_wins = false);
  bool help() const { return help_; }
  /// The usage text: synopsis, one line per flag with its default as the fields hold it now,
  /// then the notes.
  std::string usage() const;
  const std::vector<CliFlag>& flags() const { return flags_; }

 private:
  CliParser& add(CliFlag flag);
  const CliFlag* find(const std::string& name) const;

  std::string synopsis_;
  std::string notes_;
  std::vector<CliFlag> flags_;
  bool help_ = false;
};

/// The value parsers the table uses, for tools' custom flags. Each throws InputError
/// "<flag>: '<value>' is not ..." or "<flag>: <value> is not in <range>".
int parseCliInteger(const std::string& flag, const std::string& value, CliRange range);
double parseCliReal(const std::string& flag, const std::string& value, CliRange range);
/// A comma-separated list of 1..max_items numbers, each in `range` (the reals flag's parse).
std::vector<double> parseCliReals(const std::string& flag, const std::string& value, CliRange range,
                                  int max_items);
/// A number as --help shows it (shortest round trip, at most 6 significant digits).
std::string formatCliNumber(double x);

}  // namespace flapsim
