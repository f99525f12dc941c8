// The checkpoint of an evolution as text: every double as a C99 hex float (it reads back bit
// for bit), every count and number checked on reading against the limits of a run.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "flapsim/cli_args.h"
#include "flapsim/evolve.h"
#include "flapsim/evolve_args.h"
#include "flapsim/text_file.h"

namespace flapsim {

namespace {

std::string hex(double x) {
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%a", x);
  return buf;
}

class CheckpointReader {
 public:
  explicit CheckpointReader(const std::string& text) : in_(text) {}
  std::istringstream line(const std::string& what) { return std::istringstream(rawLine(what)); }
  std::string rawLine(const std::string& what) {
    std::string l;
    if (!std::getline(in_, l)) fail("missing " + what);
    ++number_;
    if (l.size() > kMaxTextValue) fail("a line of " + std::to_string(l.size()) + " characters");
    return l;
  }
  void expect(std::istringstream& l, const std::string& word) {
    std::string w;
    if (!(l >> w) || w != word) fail("expected '" + word + "'");
  }
  // A whole number in [lo, hi]: digits with an optional '-', no wrap.
  long long integer(std::istringstream& l, const std::string& what, long long lo, long long hi) {
    std::string w;
    if (!(l >> w)) fail("expected an integer (" + what + ")");
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(w.c_str(), &end, 10);
    if (end == w.c_str() || *end != '\0' || errno == ERANGE || v < lo || v > hi) {
      fail(quoteValue(w) + " is not an integer in [" + std::to_string(lo) + ", " +
           std::to_string(hi) + "] (" + what + ")");
    }
    return v;
  }
  double real(std::istringstream& l, const std::string& what) {
    std::string w;
    if (!(l >> w)) fail("expected a number (" + what + ")");
    char* end = nullptr;
    const double v = std::strtod(w.c_str(), &end);
    if (end == w.c_str() || *end != '\0' || !std::isfinite(v)) {
      fail(quoteValue(w) + " is not a finite number (" + what + ")");
    }
    return v;
  }
  // Nothing but white space is left.
  void finish() {
    std::string rest;
    if (in_ >> rest) fail("unexpected " + quoteValue(rest) + " after 'end'");
  }
  void done(std::istringstream& l) {
    std::string rest;
    if (l >> rest) fail("unexpected " + quoteValue(rest) + " at the end of the line");
  }
  [[noreturn]] void fail(const std::string& msg) const {
    throw InputError("checkpoint line " + std::to_string(number_) + ": " + msg);
  }

 private:
  std::istringstream in_;
  int number_ = 0;
};

void readHead(CheckpointReader& r, EvolveCheckpoint& c) {
  auto l = r.line("header");
  r.expect(l, "flapsim_checkpoint");
  if (r.integer(l, "version", 1, 1) != 1) r.fail("unknown version");
  r.done(l);
  l = r.line("generation");
  r.expect(l, "generation");
  c.generation = static_cast<int>(r.integer(l, "generation", 0, kMaxGenerations));
  r.done(l);
  l = r.line("seed");
  r.expect(l, "seed");
  std::string seed;
  if (!(l >> seed)) r.fail("expected the seed");
  try {
    CliParser("").seed("seed", "S", &c.seed, "").parse({"seed", seed});
  } catch (const InputError& e) {
    r.fail(e.what());
  }
  r.done(l);
  l = r.line("args");
  r.expect(l, "args");
  const long long n_args = r.integer(l, "args", 0, static_cast<long long>(kMaxSpecArgs));
  r.done(l);
  for (long long i = 0; i < n_args; ++i) c.args.push_back(r.rawLine("an argument"));
}

void readPopulation(CheckpointReader& r, EvolveCheckpoint& c) {
  auto l = r.line("population");
  r.expect(l, "population");
  const long long n = r.integer(l, "individuals", 2, kMaxPopulation);
  const long long genes = r.integer(l, "genes", 1, kMaxGenes);
  long long objectives = 0;  // NSGA-II's, after the genes
  std::string word;
  if (l >> word) {
    if (word != "objectives") r.fail("expected 'objectives' or the end of the line");
    objectives = r.integer(l, "objectives", 1, kMaxObjectives);
  }
  r.done(l);
  for (long long i = 0; i < n; ++i) {
    auto row = r.line("an individual");
    Individual ind;
    ind.fitness = r.real(row, "fitness");
    for (long long g = 0; g < genes; ++g) ind.genes.push_back(r.real(row, "gene"));
    for (long long m = 0; m < objectives; ++m) ind.objectives.push_back(r.real(row, "objective"));
    r.done(row);
    c.population.push_back(std::move(ind));
  }
  l = r.line("history");
  r.expect(l, "history");
  const long long h = r.integer(l, "generations", c.generation + 1, c.generation + 1);
  r.done(l);
  for (long long i = 0; i < h; ++i) {
    auto row = r.line("a generation");
    GenerationStats s;
    s.generation = static_cast<int>(r.integer(row, "generation", i, i));
    s.best = r.real(row, "best");
    s.mean = r.real(row, "mean");
    s.worst = r.real(row, "worst");
    s.evaluations = static_cast<int>(r.integer(row, "evaluations", 0, kMaxPopulation));
    const long long bg = r.integer(row, "best genes", genes, genes);
    for (long long g = 0; g < bg; ++g) s.best_genes.push_back(r.real(row, "gene"));
    r.done(row);
    c.history.push_back(std::move(s));
  }
}

}  // namespace

std::string checkpointToText(const EvolveCheckpoint& c) {
  std::ostringstream out;
  const size_t genes = c.population.empty() ? 0 : c.population.front().genes.size();
  out << "flapsim_checkpoint 1\n"
      << "generation " << c.generation << "\n"
      << "seed " << c.seed << "\n"
      << "args " << c.args.size() << "\n";
  for (const auto& a : c.args) out << a << "\n";
  const size_t objectives = c.population.empty() ? 0 : c.population.front().objectives.size();
  out << "population " << c.population.size() << " " << genes;
  if (objectives > 0) out << " objectives " << objectives;
  out << "\n";
  for (const auto& ind : c.population) {
    out << hex(ind.fitness);
    for (double g : ind.genes) out << " " << hex(g);
    for (double f : ind.objectives) out << " " << hex(f);
    out << "\n";
  }
  out << "history " << c.history.size() << "\n";
  for (const auto& h : c.history) {
    out << h.generation << " " << hex(h.best) << " " << hex(h.mean) << " " << hex(h.worst) << " "
        << h.evaluations << " " << h.best_genes.size();
    for (double g : h.best_genes) out << " " << hex(g);
    out << "\n";
  }
  out << "end\n";
  return out.str();
}

EvolveCheckpoint checkpointFromText(const std::string& text) {
  CheckpointReader r(text);
  EvolveCheckpoint c;
  readHead(r, c);
  readPopulation(r, c);
  auto l = r.line("end");
  r.expect(l, "end");
  r.done(l);
  r.finish();
  return c;
}

EvolveCheckpoint readCheckpointFile(const std::string& path) {
  try {
    EvolveCheckpoint c = checkpointFromText(readTextFile(path, kMaxCheckpointBytes));
    checkSpecArgs(c.args);
    return c;
  } catch (const InputError& e) {
    const std::string what = e.what();
    throw InputError(what.rfind(path, 0) == 0 ? what : path + ": " + what);
  }
}

void writeCheckpointFile(const std::string& path, const EvolveCheckpoint& checkpoint) {
  writeTextFile(path + ".tmp", checkpointToText(checkpoint));
  std::filesystem::rename(path + ".tmp", path);
}

}  // namespace flapsim
