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
#include "pbdrrViewList.h"
#include "pbdrrMessages.h"

#include <algorithm>
#include <fstream>
#include <map>
#include <set>

namespace pbdrr
{
std::vector<ViewSpec>
MakeSweep(unsigned count, double startDegrees, double stepDegrees)
{
  std::vector<ViewSpec> views(count);
  for (unsigned k = 0; k < count; ++k)
  {
    views[k].GantryDegrees = startDegrees + static_cast<double>(k) * stepDegrees;
  }
  return views;
}

const std::vector<std::string> &
ViewsFileColumns()
{
  static const std::vector<std::string> columns = { "gantry",   "nrm_x",    "nrm_y", "nrm_z", "vup_x", "vup_y",
                                                    "vup_z",    "iso_x",    "iso_y", "iso_z", "sad",   "sid",
                                                    "offset_u", "offset_v", "tx",    "ty",    "tz",    "rx",
                                                    "ry",       "rz",       "output" };
  return columns;
}

std::string
TrimSpaces(const std::string & text)
{
  const size_t begin = text.find_first_not_of(" \t\r");
  if (begin == std::string::npos)
  {
    return std::string();
  }
  return text.substr(begin, text.find_last_not_of(" \t\r") + 1 - begin);
}

std::vector<std::string>
SplitCsvCells(const std::string & line)
{
  std::vector<std::string> cells;
  size_t                   begin = 0;
  for (size_t end; (end = line.find(',', begin)) != std::string::npos; begin = end + 1)
  {
    cells.push_back(TrimSpaces(line.substr(begin, end - begin)));
  }
  cells.push_back(TrimSpaces(line.substr(begin)));
  return cells;
}

void
ForEachCsvRow(std::istream &                                                                             stream,
              const std::string &                                                                        name,
              const std::function<void(size_t, const std::string &, const std::vector<std::string> &)> & row)
{
  size_t lineNumber = 0;
  for (std::string line; std::getline(stream, line);)
  {
    ++lineNumber;
    const std::string content = TrimSpaces(line);
    const std::string where = name + " line " + std::to_string(lineNumber);
    if (content.empty() || content[0] == '#')
    {
      continue;
    }
    if (content.find('\0') != std::string::npos)
    {
      throw UsageError(where + ": not text (the file is CSV)");
    }
    row(lineNumber, where, SplitCsvCells(content));
  }
  if (stream.bad())
  {
    throw UsageError(name + ": cannot read the file");
  }
}

std::map<std::string, size_t>
ReadCsvHeader(const std::vector<std::string> & cells, const std::vector<std::string> & known, const std::string & where)
{
  std::map<std::string, size_t> columns;
  for (size_t c = 0; c < cells.size(); ++c)
  {
    const std::string name = Lowercase(cells[c]);
    if (std::find(known.begin(), known.end(), name) == known.end())
    {
      throw UsageError(where + ": unknown column '" + cells[c] +
                       "' (the header names the columns: " + JoinWords(known, ", ") + ")");
    }
    if (!columns.emplace(name, c).second)
    {
      throw UsageError(where + ": the column " + name + " is named twice");
    }
  }
  return columns;
}

namespace
{
/** The column groups given whole: a vector is its three (or two) columns, or none of them. */
const std::vector<std::vector<std::string>> &
ColumnGroups()
{
  static const std::vector<std::vector<std::string>> groups = { { "nrm_x", "nrm_y", "nrm_z" },
                                                                { "vup_x", "vup_y", "vup_z" },
                                                                { "iso_x", "iso_y", "iso_z" },
                                                                { "offset_u", "offset_v" },
                                                                { "tx", "ty", "tz", "rx", "ry", "rz" } };
  return groups;
}

/** Reads one line's cells into a view; where is "FILE line N". */
class ViewLineReader
{
public:
  ViewLineReader(const std::map<std::string, size_t> & columns,
                 const std::vector<std::string> &      cells,
                 std::string                           where)
    : m_Columns(columns), m_Cells(cells), m_Where(std::move(where))
  {}

  std::optional<double>
  Number(const std::string & column) const
  {
    const auto found = m_Columns.find(column);
    if (found == m_Columns.end() || m_Cells[found->second].empty())
    {
      return std::nullopt;
    }
    return ParseNumber(m_Cells[found->second], m_Where + ": " + column);
  }

  template <size_t N>
  std::optional<std::array<double, N>>
  Group(const std::vector<std::string> & names) const
  {
    std::array<double, N> values{};
    size_t                given = 0;
    for (size_t i = 0; i < N; ++i)
    {
      const auto value = this->Number(names[i]);
      given += value ? 1 : 0;
      values[i] = value.value_or(0.0);
    }
    if (given != 0 && given != N)
    {
      throw UsageError(m_Where + ": " + names.front() + " .. " + names.back() + " are given together or left empty");
    }
    return given ? std::optional<std::array<double, N>>(values) : std::nullopt;
  }

  std::string
  Text(const std::string & column) const
  {
    const auto found = m_Columns.find(column);
    return found == m_Columns.end() ? std::string() : m_Cells[found->second];
  }

private:
  const std::map<std::string, size_t> & m_Columns;
  const std::vector<std::string> &      m_Cells;
  std::string                           m_Where;
};

double
PositiveDistance(const std::optional<double> & value, const std::string & where, const char * name)
{
  if (value && !(*value > 0.0))
  {
    throw UsageError(where + ": " + name + " must be a positive distance in mm");
  }
  return value.value_or(0.0);
}
} // namespace

std::vector<ViewSpec>
ReadViewsFile(const std::string & path)
{
  std::ifstream file(path);
  if (!file)
  {
    throw UsageError("--views " + path + ": cannot open the file");
  }
  return ReadViewsFromStream(file, path);
}

std::vector<ViewSpec>
ReadViewsFromStream(std::istream & file, const std::string & path)
{
  std::map<std::string, size_t> columns;
  size_t                        columnCount = 0;
  std::vector<ViewSpec>         views;
  ForEachCsvRow(file, path, [&](size_t lineNumber, const std::string & where, const std::vector<std::string> & cells) {
    if (columns.empty())
    {
      columns = ReadCsvHeader(cells, ViewsFileColumns(), where);
      for (const auto & group : ColumnGroups())
      {
        const size_t given =
          std::count_if(group.begin(), group.end(), [&](const auto & c) { return columns.count(c); });
        if (given != 0 && given != group.size())
        {
          throw UsageError(where + ": the columns " + JoinWords(group, " ") + " come together");
        }
      }
      columnCount = cells.size();
      return;
    }
    if (cells.size() != columnCount)
    {
      throw UsageError(where + ": " + std::to_string(cells.size()) + " cells, the header has " +
                       std::to_string(columnCount));
    }
    const ViewLineReader reader(columns, cells, where);
    ViewSpec             view;
    view.Line = lineNumber;
    view.GantryDegrees = reader.Number("gantry");
    view.Normal = reader.Group<3>({ "nrm_x", "nrm_y", "nrm_z" });
    view.ViewUp = reader.Group<3>({ "vup_x", "vup_y", "vup_z" });
    view.Isocenter = reader.Group<3>({ "iso_x", "iso_y", "iso_z" });
    view.Sad = reader.Number("sad");
    view.Sid = reader.Number("sid");
    PositiveDistance(view.Sad, where, "sad");
    PositiveDistance(view.Sid, where, "sid");
    view.Offset = reader.Group<2>({ "offset_u", "offset_v" });
    view.Pose = reader.Group<6>({ "tx", "ty", "tz", "rx", "ry", "rz" });
    view.Output = reader.Text("output");
    if (view.GantryDegrees && view.Normal)
    {
      throw UsageError(where + ": give gantry or nrm_x nrm_y nrm_z, not both");
    }
    if (view.Output.find('/') != std::string::npos || view.Output == "." || view.Output == "..")
    {
      throw UsageError(where + ": output '" + view.Output + "' must be a file name (it goes in the -o folder)");
    }
    views.push_back(view);
  });
  if (columns.empty())
  {
    throw UsageError("--views " + path + ": empty (a header line naming the columns, then one view per line)");
  }
  if (views.empty())
  {
    throw UsageError("--views " + path + ": a header but no view");
  }
  return views;
}

std::string
DescribeView(const ViewSpec & view, uint64_t index, const std::string & file)
{
  return "view " + std::to_string(index) + (view.Line ? " (" + file + " line " + std::to_string(view.Line) + ")" : "");
}
} // namespace pbdrr
