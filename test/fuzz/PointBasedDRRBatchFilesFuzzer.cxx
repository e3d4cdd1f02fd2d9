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

// libFuzzer target: the files that describe a batch's views (docs/fuzzing.md). The first byte chooses the format, the
// rest is the file's text: even, a views file (pbdrr::ReadViewsFromStream(), CSV); odd, RTK's projection geometry XML
// (itk::DRRRTKGeometryFileIO::ReadFromStream()). A pbdrr::UsageError (views) or an itk::ExceptionObject (RTK) is a
// valid outcome. Findings (abort): any other exception, a crash or a sanitizer report; an accepted views file with no
// view, a number that is not finite, a non-positive SAD or SID, an output name with a folder; an accepted RTK file
// whose views VerifyGeometry() refuses or whose source or projection matrix is not finite.

#include "itkDRRRTKGeometryFileIO.h"
#include "pbdrrOptions.h"
#include "pbdrrViewList.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>

namespace
{
[[noreturn]] void
Finding(const std::string & what, const std::string & text)
{
  std::cerr << "PointBasedDRRBatchFilesFuzzer finding: " << what << "\n--- file ---\n" << text << "\n---\n";
  std::abort();
}

template <size_t N>
bool
Finite(const std::optional<std::array<double, N>> & values)
{
  if (values)
  {
    for (double v : *values)
    {
      if (!std::isfinite(v))
      {
        return false;
      }
    }
  }
  return true;
}

void
FuzzViewsFile(const std::string & text)
{
  std::istringstream           stream(text);
  std::vector<pbdrr::ViewSpec> views;
  try
  {
    views = pbdrr::ReadViewsFromStream(stream, "fuzz.csv");
  }
  catch (const pbdrr::UsageError &)
  {
    return;
  }
  if (views.empty())
  {
    Finding("ReadViewsFromStream() accepted a file with no view", text);
  }
  for (const auto & view : views)
  {
    const bool finite = (!view.GantryDegrees || std::isfinite(*view.GantryDegrees)) && Finite(view.Normal) &&
                        Finite(view.ViewUp) && Finite(view.Isocenter) && Finite(view.Offset) && Finite(view.Pose);
    if (!finite)
    {
      Finding("ReadViewsFromStream() accepted a number that is not finite", text);
    }
    if ((view.Sad && !(*view.Sad > 0.0 && std::isfinite(*view.Sad))) ||
        (view.Sid && !(*view.Sid > 0.0 && std::isfinite(*view.Sid))))
    {
      Finding("ReadViewsFromStream() accepted a SAD or SID that is not a positive distance", text);
    }
    if (view.Output.find('/') != std::string::npos || view.Line == 0)
    {
      Finding("ReadViewsFromStream() accepted an output name with a folder, or a view without its line", text);
    }
  }
}

void
FuzzRTKGeometry(const std::string & text)
{
  auto io = itk::DRRRTKGeometryFileIO::New();
  io->SetDetectorSize({ { 8, 6 } });
  std::istringstream                          stream(text);
  itk::DRRRTKGeometryFileIO::GeometryListType geometries;
  try
  {
    geometries = io->ReadFromStream(stream, "fuzz.xml");
  }
  catch (const itk::ExceptionObject &)
  {
    return;
  }
  for (const auto & geometry : geometries)
  {
    try
    {
      geometry->VerifyGeometry();
    }
    catch (const itk::ExceptionObject & e)
    {
      Finding(std::string("ReadFromStream() gave a view VerifyGeometry() refuses: ") + e.GetDescription(), text);
    }
    const auto source = geometry->GetSourcePosition();
    bool       finite = std::isfinite(source[0]) && std::isfinite(source[1]) && std::isfinite(source[2]);
    if (geometry->HasProjectionMatrix())
    {
      const auto matrix = geometry->GetProjectionMatrix();
      for (unsigned r = 0; r < 3; ++r)
      {
        for (unsigned c = 0; c < 4; ++c)
        {
          finite = finite && std::isfinite(matrix[r][c]);
        }
      }
    }
    if (!finite)
    {
      Finding("ReadFromStream() gave a view whose source or projection matrix is not finite", text);
    }
  }
}
} // namespace

extern "C" int
LLVMFuzzerTestOneInput(const uint8_t * data, size_t size)
{
  if (size == 0)
  {
    return 0;
  }
  const std::string text(reinterpret_cast<const char *>(data + 1), size - 1);
  try
  {
    if (data[0] % 2 == 0)
    {
      FuzzViewsFile(text);
    }
    else
    {
      FuzzRTKGeometry(text);
    }
  }
  catch (const std::exception & e)
  {
    Finding(std::string("an unexpected exception: ") + e.what(), text);
  }
  return 0;
}
