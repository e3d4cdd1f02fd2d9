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
#ifndef pbdrrBatch_h
#define pbdrrBatch_h

#include "pbdrrOptions.h"
#include "pbdrrViewList.h"

#include <cstdint>
#include <string>
#include <vector>

namespace pbdrr
{
/** The seed of view k's points under --independent-views: a SplitMix64 hash of (seed, k), so that views draw
 * independent points, and view k the same ones in any run, shard or thread count. */
uint64_t
ViewSeed(uint64_t seed, uint64_t k);

/** A batch of views of one volume, checked and resolved before any load: the views, each one's output path, and the
 * views this run renders (all, a shard, one --view-index; less those --resume finds done). */
struct BatchPlan
{
  std::vector<ViewSpec>    Views;
  std::vector<std::string> Outputs;      ///< view k's image (numbered files; for a stack, every entry is the stack)
  std::string              ViewsFrom;    ///< where the views come from, for messages ("--angles", a file's path)
  std::vector<uint64_t>    Selected;     ///< the views to render, ascending
  uint64_t                 Skipped{ 0 }; ///< views of the selection --resume found done
};

/** Plans the batch of options: reads the views (--angles, --views or --rtk-geometry), checks every option and view
 * (the views file's bad line named by its number, a pattern without a counter, duplicate outputs, an output folder
 * that cannot be written, --shard, --view-index) and, with --resume, leaves out the views whose files exist.
 * shardOffset numbers the first view for --shard (a manifest's earlier views), so that shards cut across volumes.
 * Throws UsageError or std::runtime_error; writes nothing. */
BatchPlan
PlanBatch(const Options & options, uint64_t shardOffset = 0);

/** Seconds on the steady clock: the batch's timings and its progress line. */
double
SteadySeconds();

/** Counts views done for a batch's progress: views done / total, views per second and the time left, on a terminal
 * as one line redrawn, into a log (a Slurm job's) as a line every 10 seconds; nothing when quiet. */
class BatchProgress
{
public:
  /** Progress of total views; disabled: silent. */
  BatchProgress(uint64_t total, bool enabled);
  ~BatchProgress();

  /** One more view done. */
  void
  ViewDone();

  /** Clears the terminal line and prints the summary: views, seconds, views per second. */
  void
  Finish();

private:
  void
  Print(bool final);

  uint64_t m_Total;
  uint64_t m_Done{ 0 };
  bool     m_Enabled;
  bool     m_Terminal;
  bool     m_Finished{ false };
  double   m_Start;
  double   m_LastPrint;
};

/** Renders the plan's selected views of the volume options.input, loaded once: the kept points re-projected per view
 * (one draw for every view: PointBasedDRRImageFilter's ReusePoints), or new points per view (--independent-views,
 * seed ViewSeed(seed, k)), or the exact projector; writes each view's image and geometry through temporary names, or
 * the stack. */
void
RenderBatch(const Options & options, const BatchPlan & plan, BatchProgress & progress);

/** pbdrr's batch mode: PlanBatch(), then RenderBatch(). */
void
RunBatch(const Options & options);
} // namespace pbdrr

#endif
