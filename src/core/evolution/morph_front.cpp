#include "flapsim/morph_front.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "flapsim/ga.h"
#include "flapsim/pareto.h"

namespace flapsim {

std::vector<MorphScore> morphScores(const std::vector<std::vector<double>>& genomes,
                                    const EvaluationSpec& spec, int threads) {
  if (spec.kind != EvolveKind::kMorph) throw InputError("morph scores: the spec is not a morph's");
  const EpisodeParams& e = spec.episode;
  // Drawn as the evolution's runner draws them: on hover_1, whose link names (all the draws
  // read) every body shares.
  const CreatureModelPtr hover_1 = parseCreatureModel(makeHoverUrdf("hover"), "hover_1");
  const std::vector<EpisodeStart> starts = episodeStarts(e, hover_1.get());
  const int n = static_cast<int>(starts.size());
  struct Flight {
    double power_per_kg = 0.0, loss = 0.0, mass = 0.0;
    std::string refusal;
  };
  std::vector<Flight> flights(genomes.size() * starts.size());
  parallelMap(static_cast<int>(flights.size()), threads, [&](int task) {
    const MorphFlight flight =
        flyMorphEpisode(genomes[task / n], e, starts[task % n], spec.morph.budget);
    Flight& f = flights[task];
    f.refusal = flight.refusal;
    if (!f.refusal.empty()) return 0.0;
    f.power_per_kg = flight.result.specificPower();
    f.mass = flight.result.mass;
    f.loss = morphLoss(flight.result, e);
    return 0.0;
  });
  std::vector<MorphScore> scores(genomes.size());
  for (size_t i = 0; i < genomes.size(); ++i) {
    MorphScore& s = scores[i];
    for (int k = 0; k < n; ++k) {
      const Flight& f = flights[i * n + k];
      s.refusal = f.refusal;
      s.power_per_kg += f.power_per_kg / n;
      s.loss += f.loss / n;
      s.mass = f.mass;
    }
  }
  return scores;
}

std::vector<int> morphRanks(const std::vector<MorphScore>& scores) {
  ObjectiveTable built;
  std::vector<size_t> which;
  for (size_t i = 0; i < scores.size(); ++i) {
    if (!scores[i].refusal.empty()) continue;
    built.push_back({scores[i].power_per_kg, scores[i].loss});
    which.push_back(i);
  }
  std::vector<int> ranks(scores.size(), -1);
  if (built.empty()) return ranks;
  const std::vector<int> r = paretoRanks(built);
  for (size_t k = 0; k < which.size(); ++k) ranks[which[k]] = r[k];
  return ranks;
}

std::string morphFrontCsv(const std::vector<std::vector<double>>& genomes,
                          const std::vector<MorphScore>& scores, const std::vector<int>& ranks,
                          const MassBudget& budget) {
  std::ostringstream out;
  out << "member,rank,power_w_per_kg,loss_m,mass_g";
  for (const BodyGene& g : bodyGenes()) out << "," << g.name;
  out << ",motors_g,ballast_g,refusal\n";
  char cell[64];
  for (size_t i = 0; i < genomes.size(); ++i) {
    const MorphScore& s = scores[i];
    std::snprintf(cell, sizeof cell, "%zu,%d,%.4f,%.6f,%.4f", i, ranks[i], s.power_per_kg, s.loss,
                  1e3 * s.mass);
    out << cell;
    const std::vector<double> body(genomes[i].begin() + kHoverGeneCount, genomes[i].end());
    const HoverParams p = bodyFromGenes(body, budget);
    for (const BodyGene& g : bodyGenes()) {
      std::snprintf(cell, sizeof cell, ",%.6g", p.*g.member);
      out << cell;
    }
    const BodyMass m = bodyMass(p, budget);
    std::snprintf(cell, sizeof cell, ",%.4f,%.4f,", 1e3 * m.motors, 1e3 * m.ballast);
    std::string refusal = s.refusal;
    std::replace(refusal.begin(), refusal.end(), ',', ';');
    out << cell << refusal << "\n";
  }
  return out.str();
}

std::string morphFrontGnuplot(const std::string& dir) {
  std::ostringstream g;
  g << "set datafile separator ','\n"
    << "set terminal pngcairo size 800,500 font 'sans,11'\n"
    << "set grid\nset logscale y\nset key top right\n"
    << "set output '" << dir << "/front.png'\n"
    << "set title 'The last population: loss against power (both minimised)'\n"
    << "set xlabel 'mean positive mechanical power (W/kg)'\n"
    << "set ylabel 'mean loss: altitude rms, tilt, sag, fall, flips (m)'\n"
    << "plot '" << dir << "/front.csv' using ($2 == 0 ? $3 : 1/0):4 skip 1 with points pt 7 "
    << "ps 1.6 title 'front (rank 0)', \\\n"
    << "     '' using ($2 > 0 ? $3 : 1/0):4 skip 1 with points pt 6 ps 1.2 title 'dominated'\n"
    << "unset output\n";
  return g.str();
}

}  // namespace flapsim
