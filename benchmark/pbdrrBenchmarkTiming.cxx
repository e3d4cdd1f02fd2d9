/*=========================================================================
 *
 *  Copyright NumFOCUS and the PointBasedDRR contributors
 *
 *  Licensed under the Apache License, Version 2.0 (the "License");
 *  you may not use this file except in compliance with the License.
 *  You may obtain a copy of the License at
 *
 *         http://www.apache.org/licenses/LICENSE-2.0.txt
 *
 *  Unless required by applicable law or agreed to in writing, software
 *  distributed under the License is distributed on an "AS IS" BASIS,
 *  WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
 *  See the License for the specific language governing permissions and
 *  limitations under the License.
 *
 *=========================================================================*/
#include "pbdrrBenchmarkTiming.h"

#include <algorithm>
#include <fstream>
#include <string>
#include <vector>

namespace pbdrr
{
namespace bench
{
namespace
{
/** A field of /proc/self/status in MiB (VmHWM, VmRSS); NaN if absent. */
double
StatusMiB(const std::string & key)
{
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
  {
    if (line.compare(0, key.size() + 1, key + ":") == 0)
      return std::stod(line.substr(key.size() + 1)) / 1024.0;
  }
  return NaN;
}

/** Resets the peak resident set size (VmHWM) to the current one (Linux >= 4.0). */
void
ResetPeakMemory()
{
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
}
} // namespace

Timing
Measure(const std::function<void()> & render, unsigned int runs, double repeatLimit)
{
  ResetPeakMemory();
  const double        base = StatusMiB("VmRSS");
  std::vector<double> walls, cpus;
  for (unsigned int r = 0; r < runs; ++r)
  {
    const double cpu0 = CpuSeconds();
    const double wall0 = Now();
    render();
    walls.push_back(Now() - wall0);
    cpus.push_back(CpuSeconds() - cpu0);
    if (walls.front() > repeatLimit)
      break;
  }
  Timing timing;
  timing.Runs = static_cast<unsigned>(walls.size());
  timing.Wall = Median(walls);
  timing.WallMin = *std::min_element(walls.begin(), walls.end());
  timing.WallMax = *std::max_element(walls.begin(), walls.end());
  timing.Cpu = Median(cpus);
  timing.PeakMiB = StatusMiB("VmHWM");
  timing.ExtraMiB = timing.PeakMiB - base;
  return timing;
}
} // namespace bench
} // namespace pbdrr
