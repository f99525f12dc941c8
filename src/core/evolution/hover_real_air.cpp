// flight_check --hover --real-air: the hover creature under its controller from held-out starts
// in real air (flapsim/flight_check.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "flapsim/flight_check.h"
#include "flapsim/hover_evolution.h"
#include "flapsim/hover_flight.h"

namespace flapsim {

bool HoverCheckRun::passed() const {
  return !flight.flipped && flight.min_upright > 0.5 && flight.altitude_rms < 0.3 &&
         std::abs(flight.mean_bank) < 5.0 * M_PI / 180.0;
}

std::vector<HoverCheckRun> hoverRealAirCheck(
    const CreatureModelPtr& model, const FlightCheckOptions& o,
    const std::function<void(const EpisodeStart&, HoverFlightParams&)>& adjust) {
  FlightCheckParams p = realAirParams(o.params, *model);
  const HoverControllerParams controller = hoverCheckController(o);
  p.altitude = controller.altitude;
  const EpisodeParams episode = flightCheckEpisodes(p);
  const std::vector<EpisodeStart> starts = episodeStarts(episode, model.get());
  std::vector<HoverCheckRun> runs(starts.size());
  parallelMap(static_cast<int>(starts.size()), p.threads, [&](int i) {
    const EpisodeStart& start = starts[static_cast<size_t>(i)];
    // The hover episode's flight (the evolution's), from the altitude held, flown to its end,
    // with real air's gusts, gyro bias and altimeter noise.
    HoverFlightParams f = hoverEpisodeFlight(episode, start, controller.altitude);
    f.start_height.reset();
    f.end_on_flip = false;
    f.gusts = episode;
    f.gust_start = start;
    if (adjust) adjust(start, f);
    runs[static_cast<size_t>(i)] = HoverCheckRun{flyHover(model, controller, f), start};
    return 0.0;
  });
  return runs;
}

std::string hoverRealAirReport(const FlightCheckOptions& o, const std::vector<HoverCheckRun>& runs,
                               int& failed) {
  constexpr double kDeg = 180.0 / M_PI;
  // As flight_check's network table: one word a column (heights after the settling time).
  std::string out =
      "start    roll   pitch      wind flipped up_set lowest_up   min_z   max_z  alt_rms    bank"
      "    drift      P+/m result\n";
  failed = 0;
  double power = 0.0;
  for (size_t i = 0; i < runs.size(); ++i) {
    const HoverCheckRun& r = runs[i];
    const HoverFlightResult& f = r.flight;
    const Vec3& w = r.start.wind;
    char line[256];
    char wind[32];
    std::snprintf(wind, sizeof wind, "%.1f@%.0f°", w.norm(), std::atan2(w.y(), w.x()) * kDeg);
    std::snprintf(line, sizeof line,
                  "%-5zu %6.1f° %6.1f° %9s %7s %6.3f %9.3f %6.2fm %6.2fm %7.3fm %6.2f° %7.2fm "
                  "%6.0fW/kg %s\n",
                  i, r.start.roll * kDeg, r.start.pitch * kDeg, wind, f.flipped ? "yes" : "no",
                  f.min_upright, f.lowest_upright, f.min_height, f.max_height, f.altitude_rms,
                  f.mean_bank * kDeg, f.drift.norm(), f.specificPower(),
                  r.passed() ? "pass" : "FAIL");
    out += line;
    if (!r.passed()) ++failed;
    power += f.specificPower() / static_cast<double>(runs.size());
  }
  char summary[384];
  std::snprintf(summary, sizeof summary,
                "%zu of %zu starts passed (hover, %s, holding %g m, %g s at %g ms, %s; pass: "
                "no flip, up > 0.5, altitude rms < 0.3 m after 10 s, |mean bank| < 5 deg); "
                "mean %.1f W/kg\n",
                runs.size() - static_cast<size_t>(failed), runs.size(),
                o.gains.empty() ? "gains by hand" : o.gains.c_str(),
                hoverCheckController(o).altitude, o.params.duration, 1000.0 * o.params.step_size,
                realAirName(o.params).c_str(), power);
  return out + summary;
}

}  // namespace flapsim
