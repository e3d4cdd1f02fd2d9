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
#ifndef pbdrrBenchmarkTable_h
#define pbdrrBenchmarkTable_h
// The rows PointBasedDRRBenchmark measures and how they are written: OUTDIR/NAME.csv (read by
// benchmark/plot_benchmark.py), the Markdown table of OUTDIR/NAME.md and OUTDIR/NAME_agreement.csv.
#include "pbdrrBenchmarkTiming.h"

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace pbdrr
{
namespace bench
{
struct Row
{
  std::string Config, Sweep, Method, Sampler, Kernel, Splat, Model, Status{ "ok" }, Note;
  double      X{ NaN };
  uint64_t    Voxels{ 0 }, Samples{ 0 };
  unsigned    Columns{ 0 }, DetectorRows{ 0 }, Rays{ 0 };
  Timing      Time;
  double      HuToMu{ NaN }, Tables{ NaN }, TableBytes{ NaN }, TableBytesPerVoxel{ NaN };
  double      FirstRender{ NaN }; // the untimed first render of the filter at this row's setting
  Errors      Own, Box;
};

/** One image compared with another (NAME_agreement.csv). */
struct AgreementRow
{
  std::string What, Against;
  Errors      E;
};

/** `value` printed with `format`; empty if not finite. */
std::string
Format(double value, const char * format = "%.4g");

/** A sample count as 1e5, 3e5, ... (empty for 0). */
std::string
SamplesText(uint64_t n);

void
WriteCsv(const std::string & path, const std::vector<Row> & rows);

void
WriteAgreementCsv(const std::string & path, const std::vector<AgreementRow> & rows);

/** The Markdown tables of the rows and, if any, of the agreements. */
void
WriteMarkdownTables(std::ostream & md, const std::vector<Row> & rows, const std::vector<AgreementRow> & agreement);

/** The 1, 5 and 15 minute load averages. */
std::string
LoadAverage();

/** CPU model, cores, memory and ITK's threads. */
std::string
MachineText();
} // namespace bench
} // namespace pbdrr

#endif
