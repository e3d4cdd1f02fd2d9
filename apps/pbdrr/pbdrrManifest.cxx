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
#include "pbdrrManifest.h"
#include "pbdrrBatch.h"
#include "pbdrrMessages.h"
#include "pbdrrOutputFiles.h"
#include "pbdrrViewList.h"

#include "itkMultiThreaderBase.h"

#include <algorithm>
#include <fstream>
#include <iostream>
#include <map>

namespace pbdrr
{
namespace
{
const std::vector<std::string> &
ManifestColumns()
{
  static const std::vector<std::string> columns = { "volume", "output", "views", "angles", "angle_step", "gantry" };
  return columns;
}

/** path as given if absolute, else from the manifest's folder. */
std::string
FromFolder(const std::string & folder, const std::string & path)
{
  return path.empty() || path[0] == '/' || folder == "." ? path : folder + "/" + path;
}
} // namespace

std::vector<ManifestEntry>
ReadManifest(const std::string & path, const Options & commandLine)
{
  std::ifstream file(path);
  if (!file)
  {
    throw UsageError("--manifest " + path + ": cannot open the file");
  }
  const std::string             folder = DirectoryOf(path);
  std::map<std::string, size_t> columns;
  std::vector<ManifestEntry>    entries;
  ForEachCsvRow(file, path, [&](size_t lineNumber, const std::string & where, const std::vector<std::string> & cells) {
    if (columns.empty())
    {
      columns = ReadCsvHeader(cells, ManifestColumns(), where);
      for (const char * required : { "volume", "output" })
      {
        if (!columns.count(required))
        {
          throw UsageError(where + ": no " + required + " column (a manifest names each volume and its output)");
        }
      }
      return;
    }
    if (cells.size() != columns.size())
    {
      throw UsageError(where + ": " + std::to_string(cells.size()) + " cells, the header has " +
                       std::to_string(columns.size()));
    }
    const auto cell = [&](const char * name) {
      const auto found = columns.find(name);
      return found == columns.end() ? std::string() : cells[found->second];
    };
    ManifestEntry entry;
    entry.Line = lineNumber;
    entry.Batch = commandLine;
    entry.Batch.manifest.clear();
    entry.Batch.input = FromFolder(folder, cell("volume"));
    entry.Batch.output = FromFolder(folder, cell("output"));
    if (entry.Batch.input.empty() || entry.Batch.output.empty())
    {
      throw UsageError(where + ": every volume needs its volume and output cells");
    }
    const std::string views = cell("views");
    const std::string angles = cell("angles");
    if (views.empty() == angles.empty())
    {
      throw UsageError(where + ": give the views one way: a views file (views) or a sweep (angles)");
    }
    if (!views.empty())
    {
      if (!cell("angle_step").empty() || !cell("gantry").empty())
      {
        throw UsageError(where + ": angle_step and gantry belong to a sweep (angles), not to a views file");
      }
      (EndsWith(Lowercase(views), ".xml") ? entry.Batch.rtkGeometryFile : entry.Batch.viewsFile) =
        FromFolder(folder, views);
    }
    else
    {
      const double count = ParseNumber(angles, where + ": angles");
      if (count < 1 || count > 1000000 || count != static_cast<double>(static_cast<unsigned>(count)))
      {
        throw UsageError(where + ": angles expects a whole number from 1 to 1000000, got '" + angles + "'");
      }
      entry.Batch.angles = static_cast<unsigned>(count);
      if (!cell("angle_step").empty())
      {
        entry.Batch.angleStepDegrees = ParseNumber(cell("angle_step"), where + ": angle_step");
      }
      if (!cell("gantry").empty())
      {
        entry.Batch.gantryDegrees = ParseNumber(cell("gantry"), where + ": gantry");
      }
    }
    entries.push_back(entry);
  });
  if (columns.empty() || entries.empty())
  {
    throw UsageError("--manifest " + path + ": no volume (a header line naming the columns, then one volume per line)");
  }
  return entries;
}

void
RunManifest(const Options & options)
{
  // --angles, --views, --rtk-geometry, --view-index and --stack are refused before (RunBatch(): their declarations).
  const std::vector<ManifestEntry> entries = ReadManifest(options.manifest, options);
  std::vector<BatchPlan>           plans;
  uint64_t                         offset = 0, selected = 0, skipped = 0;
  std::map<std::string, size_t>    outputs; // every file of every volume, to refuse two volumes writing one
  for (const ManifestEntry & entry : entries)
  {
    const std::string where = options.manifest + " line " + std::to_string(entry.Line);
    if (!FileExists(entry.Batch.input) && !IsDirectoryPath(entry.Batch.input))
    {
      throw UsageError(where + ": the volume " + entry.Batch.input + " does not exist");
    }
    try
    {
      plans.push_back(PlanBatch(entry.Batch, offset));
    }
    catch (const UsageError & e)
    {
      throw UsageError(where + ": " + e.what());
    }
    for (const std::string & output : plans.back().Outputs)
    {
      const auto inserted = outputs.emplace(output, entry.Line);
      if (!inserted.second && inserted.first->second != entry.Line)
      {
        throw UsageError(where + ": " + output + " is written by line " + std::to_string(inserted.first->second) +
                         " too");
      }
    }
    offset += plans.back().Views.size();
    selected += plans.back().Selected.size();
    skipped += plans.back().Skipped;
  }
  const bool chatty = !options.quiet;
  if (options.threads > 0)
  {
    itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(options.threads);
  }
  if (chatty || options.verbose)
  {
    std::cerr << "pbdrr: " << selected << " of " << offset << " views of " << entries.size() << " volumes to render"
              << (skipped ? " (" + std::to_string(skipped) + " done before: --resume)" : std::string()) << std::endl;
  }
  BatchProgress progress(selected, chatty);
  for (size_t e = 0; e < entries.size(); ++e)
  {
    if (!plans[e].Selected.empty())
    {
      RenderBatch(entries[e].Batch, plans[e], progress);
    }
  }
  progress.Finish();
}
} // namespace pbdrr
