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
#ifndef pbdrrManifest_h
#define pbdrrManifest_h

#include "pbdrrOptions.h"

#include <string>
#include <vector>

namespace pbdrr
{
/** One volume of a manifest: the options of its batch (the command line's, with the row's volume, output and views). */
struct ManifestEntry
{
  size_t  Line{ 0 }; ///< its line in the manifest
  Options Batch;     ///< input, output and the views set by the row
};

/** Reads a manifest: CSV with a header, one volume per line (# comments and blank lines skipped). Columns: volume and
 * output (a pattern or a folder, as -o), and the views as a views file or RTK XML (views; .xml: RTK's) or a sweep
 * (angles, with angle_step and gantry optional). Relative paths are taken from the manifest's folder. The other options
 * come from the command line. Throws UsageError naming the line for an unknown column, a missing cell, a row without
 * views or with two kinds. */
std::vector<ManifestEntry>
ReadManifest(const std::string & path, const Options & commandLine);

/** pbdrr --manifest: plans every volume's batch before any load (every error first), then renders them, each volume
 * loaded once; --shard counts the views across the volumes in the manifest's order. */
void
RunManifest(const Options & options);
} // namespace pbdrr

#endif
