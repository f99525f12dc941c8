#include "flapsim/cli_args.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "flapsim/types.h"

namespace flapsim {

namespace {

// Longest text read as a number: a longer one is refused before it is scanned.
constexpr std::size_t kMaxNumberText = 64;

std::vector<std::string> splitNames(const std::string& names) {
  std::vector<std::string> out;
  std::istringstream in(names);
  for (std::string n; std::getline(in, n, ',');) out.push_back(n);
  return out;
}

// Every comma separates two items: "a,,b" and "a,b," have an empty item, which the item's
// parser refuses by name.
std::vector<std::string> splitList(const std::string& flag, const std::string& value,
                                   int max_items) {
  if (value.empty()) throw InputError(flag + ": an empty list");
  std::vector<std::string> items;
  for (size_t from = 0;;) {
    if (static_cast<int>(items.size()) >= max_items) {
      throw InputError(flag + ": more than " + std::to_string(max_items) + " items");
    }
    const size_t comma = value.find(',', from);
    items.push_back(value.substr(from, comma == std::string::npos ? comma : comma - from));
    if (comma == std::string::npos) break;
    from = comma + 1;
  }
  return items;
}

template <typename T>
std::string joinList(const std::vector<T>& items) {
  std::string out;
  for (const auto& x : items) {
    if (!out.empty()) out += ",";
    if constexpr (std::is_arithmetic_v<T>) {
      out += formatCliNumber(static_cast<double>(x));
    } else {
      out += x;
    }
  }
  return out;
}

std::string checkedText(const std::string& flag, const std::string& value,
                        const std::vector<std::string>& choices) {
  if (value.empty()) throw InputError(flag + ": an empty value");
  if (value.size() > kMaxTextValue) {
    throw InputError(flag + ": " + std::to_string(value.size()) +
                     " characters, over the limit of " + std::to_string(kMaxTextValue));
  }
  if (choices.empty()) return value;
  for (const auto& c : choices) {
    if (c == value) return value;
  }
  std::string list;
  for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
  throw InputError(flag + ": " + quoteValue(value) + " is not one of " + list);
}

}  // namespace

std::string CliRange::text() const {
  return (open_lo ? "(" : "[") + formatCliNumber(lo) + ", " + formatCliNumber(hi) + "]";
}

std::string quoteValue(const std::string& value) {
  if (value.size() <= kMaxQuotedValue) return "'" + value + "'";
  return "'" + value.substr(0, kMaxQuotedValue) + "...' (" + std::to_string(value.size()) +
         " characters)";
}

std::string formatCliNumber(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

int parseCliInteger(const std::string& flag, const std::string& value, CliRange range) {
  if (value.size() > kMaxNumberText) {
    throw InputError(flag + ": " + quoteValue(value) + " is not an integer");
  }
  const char* begin = value.c_str();
  char* end = nullptr;
  errno = 0;
  const long long x = std::strtoll(begin, &end, 10);
  if (value.empty() || end != begin + value.size() || errno == ERANGE) {
    throw InputError(flag + ": " + quoteValue(value) + " is not an integer");
  }
  if (!range.contains(static_cast<double>(x))) {
    throw InputError(flag + ": " + value + " is not in " + range.text());
  }
  return static_cast<int>(x);
}

double parseCliReal(const std::string& flag, const std::string& value, CliRange range) {
  if (value.size() > kMaxNumberText) {
    throw InputError(flag + ": " + quoteValue(value) + " is not a number");
  }
  const char* begin = value.c_str();
  char* end = nullptr;
  const double x = std::strtod(begin, &end);
  if (value.empty() || end != begin + value.size() || std::isspace(value[0])) {
    throw InputError(flag + ": " + quoteValue(value) + " is not a number");
  }
  if (!std::isfinite(x)) throw InputError(flag + ": " + quoteValue(value) + " is not finite");
  if (!range.contains(x)) throw InputError(flag + ": " + value + " is not in " + range.text());
  return x;
}

CliParser::CliParser(std::string synopsis, std::string notes)
    : synopsis_(std::move(synopsis)), notes_(std::move(notes)) {}

CliParser& CliParser::add(CliFlag flag) {
  flags_.push_back(std::move(flag));
  return *this;
}

CliParser& CliParser::integer(const std::string& names, const std::string& metavar, int* field,
                              CliRange range, const std::string& help) {
  const std::string flag = splitNames(names).front();
  return add(
      {splitNames(names),
       {metavar},
       help,
       "",
       [=](const std::vector<std::string>& v) { *field = parseCliInteger(flag, v[0], range); },
       [=] { return std::to_string(*field); }});
}

CliParser& CliParser::real(const std::string& names, const std::string& metavar, double* field,
                           CliRange range, const std::string& help) {
  const std::string flag = splitNames(names).front();
  return add({splitNames(names),
              {metavar},
              help,
              "",
              [=](const std::vector<std::string>& v) { *field = parseCliReal(flag, v[0], range); },
              [=] { return formatCliNumber(*field); }});
}

CliParser& CliParser::seed(const std::string& names, const std::string& metavar,
                           std::uint64_t* field, const std::string& help) {
  const std::string flag = splitNames(names).front();
  auto set = [=](const std::vector<std::string>& v) {
    const std::string& s = v[0];
    char* end = nullptr;
    errno = 0;
    const unsigned long long x = std::strtoull(s.c_str(), &end, 10);
    // Digits only: strtoull would take "-1" as 2^64 - 1.
    if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos || errno == ERANGE) {
      throw InputError(flag + ": " + quoteValue(s) + " is not an integer in [0, 2^64)");
    }
    *field = x;
  };
  return add({splitNames(names), {metavar}, help, "", set, [=] { return std::to_string(*field); }});
}

CliParser& CliParser::text(const std::string& names, const std::string& metavar, std::string* field,
                           const std::string& help, const std::vector<std::string>& choices) {
  const std::string flag = splitNames(names).front();
  return add({splitNames(names),
              {metavar},
              help,
              "",
              [=](const std::vector<std::string>& v) { *field = checkedText(flag, v[0], choices); },
              [=] { return *field; }});
}

CliParser& CliParser::flag(const std::string& names, bool* field, bool value,
                           const std::string& help) {
  return add({splitNames(names),
              {},
              help,
              "",
              [=](const std::vector<std::string>&) { *field = value; },
              {}});
}

namespace {

// A flag whose value is a comma-separated list of at most `max_items` items, each checked
// by `parse(flag, item)`; shown as the list it holds.
template <typename T, typename Parse>
CliFlag listFlag(const std::string& names, const std::string& metavar, std::vector<T>* field,
                 int max_items, const std::string& help, Parse parse) {
  const std::string flag = splitNames(names).front();
  auto set = [=](const std::vector<std::string>& v) {
    std::vector<T> out;
    for (const auto& item : splitList(flag, v[0], max_items)) out.push_back(parse(flag, item));
    *field = out;
  };
  return {splitNames(names), {metavar}, help, "", set, [=] { return joinList(*field); }};
}

}  // namespace

std::vector<double> parseCliReals(const std::string& flag, const std::string& value, CliRange range,
                                  int max_items) {
  std::vector<double> out;
  for (const auto& item : splitList(flag, value, max_items)) {
    out.push_back(parseCliReal(flag, item, range));
  }
  return out;
}

CliParser& CliParser::reals(const std::string& names, const std::string& metavar,
                            std::vector<double>* field, CliRange range, int max_items,
                            const std::string& help) {
  return add(listFlag(names, metavar, field, max_items, help,
                      [range](const std::string& flag, const std::string& item) {
                        return parseCliReal(flag, item, range);
                      }));
}

CliParser& CliParser::integers(const std::string& names, const std::string& metavar,
                               std::vector<int>* field, CliRange range, int max_items,
                               const std::string& help) {
  return add(listFlag(names, metavar, field, max_items, help,
                      [range](const std::string& flag, const std::string& item) {
                        return parseCliInteger(flag, item, range);
                      }));
}

CliParser& CliParser::texts(const std::string& names, const std::string& metavar,
                            std::vector<std::string>* field,
                            const std::vector<std::string>& choices, int max_items,
                            const std::string& help) {
  return add(listFlag(names, metavar, field, max_items, help,
                      [choices](const std::string& flag, const std::string& item) {
                        return checkedText(flag, item, choices);
                      }));
}

CliParser& CliParser::custom(const std::string& names, const std::vector<std::string>& metavars,
                             std::function<void(const std::vector<std::string>&)> set,
                             std::function<std::string()> shown, const std::string& help) {
  return add({splitNames(names), metavars, help, "", std::move(set), std::move(shown)});
}

CliParser& CliParser::tag(const std::string& tag) {
  flags_.back().tag = tag;
  return *this;
}

CliParser& CliParser::shows(std::function<std::string()> shown) {
  flags_.back().shown = std::move(shown);
  return *this;
}

const CliFlag* CliParser::find(const std::string& name) const {
  for (const CliFlag& f : flags_) {
    for (const std::string& n : f.names) {
      if (n == name) return &f;
    }
  }
  return nullptr;
}

std::vector<CliSeen> CliParser::parse(const std::vector<std::string>& args, bool skip_remaps,
                                      bool later_wins) {
  std::vector<CliSeen> seen;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (skip_remaps && a.find(":=") != std::string::npos) continue;  // __name:=, __log:=
    if (a == "--help" || a == "-h") {
      help_ = true;
      continue;
    }
    const CliFlag* f = find(a);
    if (f == nullptr) throw InputError("unknown option " + quoteValue(a) + " (see --help)");
    for (const CliSeen& before : seen) {
      if (before.flag == f && !later_wins) {
        throw InputError(a + " is given twice (or under another of its names)");
      }
    }
    CliSeen s{f, {}};
    for (const std::string& metavar : f->metavars) {
      // A value never starts with "--": that is the next flag, and this one's value is missing.
      if (i + 1 >= args.size() || args[i + 1].rfind("--", 0) == 0) {
        throw InputError(a + " needs a value (" + metavar + ")");
      }
      s.values.push_back(args[++i]);
    }
    f->set(s.values);
    seen.push_back(std::move(s));
  }
  return seen;
}

std::string CliParser::usage() const {
  std::ostringstream out;
  out << synopsis_ << "\n";
  for (const CliFlag& f : flags_) {
    std::string left = "  ";
    for (size_t k = 0; k < f.names.size(); ++k) left += (k ? ", " : "") + f.names[k];
    for (const auto& m : f.metavars) left += " " + m;
    const std::string def = f.shown ? f.shown() : "";
    out << left << std::string(left.size() < 24 ? 24 - left.size() : 1, ' ') << f.help
        << (def.empty() ? "" : " (" + def + ")") << "\n";
  }
  if (!notes_.empty()) out << notes_;
  return out.str();
}

}  // namespace flapsim
