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
#ifndef pbdrrBenchmarkTiming_h
#define pbdrrBenchmarkTiming_h
// Timing of PointBasedDRRBenchmark: wall and CPU time and peak memory of repeated renders.
#include "pbdrrBenchmarkSupport.h"

#include <functional>

namespace pbdrr
{
namespace bench
{
struct Timing
{
  unsigned int Runs{ 0 };
  double       Wall{ NaN }, WallMin{ NaN }, WallMax{ NaN }, Cpu{ NaN }, PeakMiB{ NaN }, ExtraMiB{ NaN };
  double       Render{ NaN }, Load{ NaN }; // subprocesses: what the program reports of its own time
};

/** Runs `render` up to `runs` times (once if the first run takes longer than repeatLimit): median wall and CPU time,
 * peak resident memory of the process during the runs, and its growth over the resident memory at the start. */
Timing
Measure(const std::function<void()> & render, unsigned int runs, double repeatLimit);

/** One untimed render, so that one-time work a filter may do in its first Update (beyond the preprocessing that is
 * measured on its own) stays out of the timings; returns its wall time, reported as first_render_s. */
template <typename TFilter>
double
WarmUp(TFilter * filter)
{
  const double start = Now();
  filter->Modified();
  filter->Update();
  return Now() - start;
}
} // namespace bench
} // namespace pbdrr

#endif
