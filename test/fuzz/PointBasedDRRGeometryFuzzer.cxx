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

// libFuzzer target: the bytes are the text of a geometry file (docs/fuzzing.md).
//
// The text is read as itk::DRRProjectionGeometry::ReadGeometryFile() reads a file (DRRProjectionGeometryFileIO's
// ReadFromStream()). An itk::ExceptionObject is a valid outcome, from the parser or from VerifyGeometry(). Findings
// (abort): any other exception, a crash or a sanitizer report, a geometry that VerifyGeometry() accepts but whose
// derived quantities (source, detector centre, pixel centres, 2D output origin, detector axes) are not finite, or whose
// axes are not an orthonormal frame with the normal, and such a geometry that DRRProjectionGeometryFileIO does not
// write, or writes so that reading it back does not give it bit for bit.

#include "itkDRRProjectionGeometryFileIO.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <sstream>
#include <string>

namespace
{
using GeometryType = itk::DRRProjectionGeometry;

[[noreturn]] void
Finding(const std::string & what, const std::string & text, const GeometryType * geometry)
{
  std::cerr << "PointBasedDRRGeometryFuzzer finding: " << what << "\n--- geometry file ---\n" << text << "\n---\n";
  if (geometry)
  {
    geometry->Print(std::cerr);
  }
  std::abort();
}

bool
Finite(const GeometryType::PointType & p)
{
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

bool
Finite(const GeometryType::VectorType & v)
{
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

void
CheckDerivedQuantities(const GeometryType * geometry, const std::string & text)
{
  const auto check = [&](bool ok, const char * what) {
    if (!ok)
    {
      Finding(std::string("VerifyGeometry() accepted a geometry whose ") + what, text, geometry);
    }
  };
  const auto & size = geometry->GetDetectorSize();
  const double lastColumn = static_cast<double>(size[0]) - 1.0;
  const double lastRow = static_cast<double>(size[1]) - 1.0;
  check(Finite(geometry->GetSourcePosition()), "source position is not finite");
  check(Finite(geometry->GetDetectorPlaneOrigin()), "detector plane origin is not finite");
  check(Finite(geometry->GetDetectorCenter()), "detector centre is not finite");
  check(Finite(geometry->GetPixelCenter(0.0, 0.0)), "pixel (0, 0) centre is not finite");
  check(Finite(geometry->GetPixelCenter(lastColumn, 0.0)), "pixel (cols - 1, 0) centre is not finite");
  check(Finite(geometry->GetPixelCenter(0.0, lastRow)), "pixel (0, rows - 1) centre is not finite");
  check(Finite(geometry->GetPixelCenter(lastColumn, lastRow)), "pixel (cols - 1, rows - 1) centre is not finite");
  const auto origin = geometry->GetDetectorOrigin2D();
  check(std::isfinite(origin[0]) && std::isfinite(origin[1]), "2D output origin is not finite");

  const auto u = geometry->GetColumnDirection();
  const auto v = geometry->GetRowDirection();
  const auto n = geometry->GetNormal();
  check(Finite(u) && Finite(v) && Finite(n), "detector axes are not finite");
  constexpr double tolerance = 1e-6;
  check(std::abs(u.GetNorm() - 1.0) < tolerance && std::abs(v.GetNorm() - 1.0) < tolerance &&
          std::abs(n.GetNorm() - 1.0) < tolerance,
        "detector axes are not unit vectors");
  check(std::abs(u * v) < tolerance && std::abs(u * n) < tolerance && std::abs(v * n) < tolerance,
        "detector axes and normal are not orthogonal");
}

bool
SameBits(const double * a, const double * b, unsigned int count)
{
  return std::memcmp(a, b, count * sizeof(double)) == 0;
}

/** Writes the geometry, reads it back into a default geometry: every field the same, bit for bit. */
void
CheckWriteReadBack(const GeometryType * geometry, const std::string & text)
{
  std::ostringstream written;
  auto               readBack = GeometryType::New();
  try
  {
    itk::DRRProjectionGeometryFileIO::WriteToStream(written, geometry);
    std::istringstream stream(written.str());
    itk::DRRProjectionGeometryFileIO::ReadFromStream(stream, readBack, "written");
  }
  catch (const itk::ExceptionObject & e)
  {
    Finding(std::string("a verified geometry was not written and read back: ") + e.GetDescription(), text, geometry);
  }
  const double scalars[3] = { geometry->GetSourceToIsocenterDistance(),
                              geometry->GetSourceToDetectorDistance(),
                              geometry->GetGantryAngleInDegrees() };
  const double readScalars[3] = { readBack->GetSourceToIsocenterDistance(),
                                  readBack->GetSourceToDetectorDistance(),
                                  readBack->GetGantryAngleInDegrees() };
  const bool   same =
    readBack->GetProjection() == geometry->GetProjection() && SameBits(scalars, readScalars, 3) &&
    SameBits(readBack->GetNormal().GetDataPointer(), geometry->GetNormal().GetDataPointer(), 3) &&
    SameBits(readBack->GetViewUp().GetDataPointer(), geometry->GetViewUp().GetDataPointer(), 3) &&
    SameBits(readBack->GetIsocenter().GetDataPointer(), geometry->GetIsocenter().GetDataPointer(), 3) &&
    readBack->GetDetectorSize() == geometry->GetDetectorSize() &&
    SameBits(readBack->GetDetectorSpacing().GetDataPointer(), geometry->GetDetectorSpacing().GetDataPointer(), 2) &&
    SameBits(readBack->GetDetectorOffset().GetDataPointer(), geometry->GetDetectorOffset().GetDataPointer(), 2);
  if (!same)
  {
    Finding("the geometry written and read back differs from the geometry:\n" + written.str(), text, geometry);
  }
}
} // namespace

extern "C" int
LLVMFuzzerInitialize(int *, char ***)
{
  itk::Object::GlobalWarningDisplayOff();
  return 0;
}

extern "C" int
LLVMFuzzerTestOneInput(const uint8_t * data, size_t size)
{
  const std::string  text(reinterpret_cast<const char *>(data), size);
  auto               geometry = GeometryType::New();
  std::istringstream stream(text);
  try
  {
    itk::DRRProjectionGeometryFileIO::ReadFromStream(stream, geometry, "fuzz");
  }
  catch (const itk::ExceptionObject &)
  {
    // Refused, naming the line: a valid outcome. What was parsed before the bad line must still verify or refuse.
  }
  catch (const std::exception & e)
  {
    Finding(std::string("the parser threw a std::exception that is not an itk::ExceptionObject: ") + e.what(),
            text,
            geometry);
  }
  catch (...)
  {
    Finding("the parser threw something that is not an itk::ExceptionObject", text, geometry);
  }

  try
  {
    geometry->VerifyGeometry();
  }
  catch (const itk::ExceptionObject &)
  {
    return 0;
  }
  catch (...)
  {
    Finding("VerifyGeometry() threw something that is not an itk::ExceptionObject", text, geometry);
  }
  CheckDerivedQuantities(geometry, text);
  CheckWriteReadBack(geometry, text);
  return 0;
}
