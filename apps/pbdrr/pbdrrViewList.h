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
#ifndef pbdrrViewList_h
#define pbdrrViewList_h

#include "pbdrrOptions.h"

#include "itkDRRProjectionGeometry.h"

#include <array>
#include <functional>
#include <istream>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace pbdrr
{
/** One view of a batch as given (a batch row): the fields that set it over the command line's view (which supplies
 * every field left empty: MakeView(), pbdrrView.h), its pose, its output name, or a view given whole (RTK's XML). A
 * row holds no detector size or pitch: every view of a batch has the command line's pixels. */
struct ViewSpec
{
  size_t                               Line{ 0 }; ///< its line in the views file (0: not from a file)
  std::optional<double>                GantryDegrees;
  std::optional<std::array<double, 3>> Normal; ///< unit vector from the isocenter towards the source
  std::optional<std::array<double, 3>> ViewUp;
  std::optional<std::array<double, 3>> Isocenter; ///< mm
  std::optional<double>                Sad;       ///< mm
  std::optional<double>                Sid;       ///< mm
  std::optional<std::array<double, 2>> Offset;    ///< mm along the columns and the rows
  /** The CT's rigid pose in the room for this view: tx ty tz (mm) rx ry rz (degrees), as pbdrr register's
   * (MakePoseTransform()); empty: where the CT's frame of reference puts it. */
  std::optional<std::array<double, 6>> Pose;
  std::string Output;                        ///< its output file name (relative to the -o folder); empty: the pattern's
  itk::DRRProjectionGeometry::Pointer Whole; ///< the whole view (RTK's XML), or null: the fields above
};

/** The views of a gantry sweep: view k at startDegrees + k stepDegrees, k = 0 .. count - 1 (plastimatch's -a / -N). */
std::vector<ViewSpec>
MakeSweep(unsigned count, double startDegrees, double stepDegrees);

/** Reads a views file: CSV, a header naming the columns, then one view per line (# comments and blank lines skipped).
 * Columns (ViewsFileColumns()): gantry, nrm_x nrm_y nrm_z, vup_x vup_y vup_z, iso_x iso_y iso_z, sad, sid, offset_u
 * offset_v, tx ty tz rx ry rz, output; a group of columns is given whole, an empty cell keeps the command line's value.
 * Throws UsageError naming the file and the line for anything else: unknown or repeated columns, a missing or extra
 * cell, a number that is not finite, no view. */
std::vector<ViewSpec>
ReadViewsFile(const std::string & path);

/** ReadViewsFile() of a stream; messages name the file as name. */
std::vector<ViewSpec>
ReadViewsFromStream(std::istream & stream, const std::string & name);

/** The columns a views file may have, in the order WriteViewsFile() writes them. */
const std::vector<std::string> &
ViewsFileColumns();

/** The cells of a CSV line (split at commas, spaces around each trimmed; no quoting). */
std::vector<std::string>
SplitCsvCells(const std::string & line);

/** Calls row(line number, "NAME line N", cells) for each line of a CSV stream but blank lines and # comments. Throws
 * UsageError for a line that is not text (a NUL) or a stream that cannot be read. */
void
ForEachCsvRow(std::istream &                                                                             stream,
              const std::string &                                                                        name,
              const std::function<void(size_t, const std::string &, const std::vector<std::string> &)> & row);

/** The columns a CSV header names (lower case) and their positions; throws UsageError (at where) for a name not in
 * known or named twice. */
std::map<std::string, size_t>
ReadCsvHeader(const std::vector<std::string> & cells,
              const std::vector<std::string> & known,
              const std::string &              where);

/** text without the spaces, tabs and carriage returns around it. */
std::string
TrimSpaces(const std::string & text);

/** What a view is called in messages: "view 7" and, from a file, "(views.csv line 9)". */
std::string
DescribeView(const ViewSpec & view, uint64_t index, const std::string & file);
} // namespace pbdrr

#endif
