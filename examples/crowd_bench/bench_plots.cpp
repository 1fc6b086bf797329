// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "crowd_bench/bench_plots.h"

#include <cstdio>
#include <cstdlib>

namespace si::bench {

namespace {

bool runGnuplot(const std::string& folder, const std::string& script) {
  const std::string file = folder + "/plot.gp";
  std::FILE* f = std::fopen(file.c_str(), "w");
  if (f == nullptr) {
    std::printf("(cannot write %s: no plots)\n", file.c_str());
    return false;
  }
  std::fputs(script.c_str(), f);
  std::fclose(f);
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0) {
    std::printf("(gnuplot not found: wrote %s only; install gnuplot-nox)\n", file.c_str());
    return false;
  }
  return std::system(("gnuplot " + file).c_str()) == 0;
}

}  // namespace

bool writePlots(const std::string& folder, const std::string& scene,
                const std::map<std::string, std::map<uint32_t, double>>& frame_ms,
                const std::string& error_data) {
  std::string script = "set terminal png size 900,560\nset grid\n";
  script += "set output '" + folder + "/frame_time.png'\nset logscale xy\n"
            "set xlabel 'characters'\nset ylabel 'max(CPU, GPU) ms per frame'\n"
            "set title 'Frame time against crowd size (" + scene + ")'\nplot ";
  bool first = true;
  for (const auto& [path, points] : frame_ms) {
    script += std::string(first ? "" : ", ") + "'-' with linespoints title '" + path + "'";
    first = false;
  }
  script += "\n";
  for (const auto& [path, points] : frame_ms) {
    for (const auto& [n, ms] : points) script += std::to_string(n) + " " + std::to_string(ms) + "\n";
    script += "e\n";
  }
  script += "set output '" + folder + "/gpu_vs_error.png'\nunset logscale y\n"
            "set logscale x\nset xlabel 'max vertex error (model units)'\n"
            "set ylabel 'GPU ms per frame'\nset title 'GPU time against bake error'\n"
            "plot '-' using 1:2 with points pt 7 notitle, '-' using 1:2:3 with labels offset 1,1 "
            "notitle\n" + error_data + "e\n" + error_data + "e\n";
  return runGnuplot(folder, script);
}

}  // namespace si::bench
