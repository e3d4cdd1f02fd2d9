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
#include "pbdrrView.h"
#include "pbdrrDicomLocalizerGeometry.h"
#include "pbdrrMessages.h"

#include "itkDRRProjectionMatrixFileIO.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace pbdrr
{
namespace
{
itk::Point<double, 3>
ToPoint(const std::array<double, 3> & a)
{
  itk::Point<double, 3> p;
  std::copy(a.begin(), a.end(), p.Begin());
  return p;
}

itk::Vector<double, 3>
ToVector(const std::array<double, 3> & a)
{
  itk::Vector<double, 3> v;
  std::copy(a.begin(), a.end(), v.Begin());
  return v;
}

itk::Vector<double, 2>
ToVector(const std::array<double, 2> & a)
{
  itk::Vector<double, 2> v;
  v[0] = a[0];
  v[1] = a[1];
  return v;
}

/** The flags that set a view by parts, which a whole view (--projection-matrix, --geometry-from) replaces. */
std::vector<std::string>
ViewFlagsGiven(const Options & options)
{
  std::vector<std::string>            given;
  const std::pair<bool, const char *> flags[] = { { !options.geometryFile.empty(), "--geometry" },
                                                  { options.sad.has_value(), "--sad" },
                                                  { options.sid.has_value(), "--sid" },
                                                  { options.gantryDegrees.has_value(), "--gantry" },
                                                  { options.isocenter.has_value(), "--isocenter" },
                                                  { options.normal.has_value(), "--nrm" },
                                                  { options.viewUp.has_value(), "--vup" },
                                                  { options.detectorOffset.has_value(), "--offset" },
                                                  { options.projection.has_value(), "--projection/--parallel" } };
  for (const auto & flag : flags)
  {
    if (flag.first)
    {
      given.push_back(flag.second);
    }
  }
  return given;
}

/** The view of a projection matrix file: --size is required (a matrix does not say the detector's size), --spacing DU
 * names the column pitch (the matrix gives the rows' pitch relative to it). */
itk::DRRProjectionGeometry::Pointer
MakeGeometryFromMatrix(const Options & options)
{
  if (!options.detectorSize)
  {
    throw UsageError(
      "--projection-matrix needs --size COLS ROWS: a projection matrix does not say the detector's size");
  }
  auto matrixReader = itk::DRRProjectionMatrixFileIO::New();
  matrixReader->SetFileName(options.projectionMatrixFile);
  const auto matrix = matrixReader->Read();
  auto       geometry = itk::DRRProjectionGeometry::New();
  if (options.detectorSpacing)
  {
    geometry->SetDetectorSpacing(ToVector(*options.detectorSpacing));
  }
  geometry->SetProjectionMatrix(matrix,
                                { { static_cast<itk::SizeValueType>((*options.detectorSize)[0]),
                                    static_cast<itk::SizeValueType>((*options.detectorSize)[1]) } });
  geometry->VerifyGeometry();
  return geometry;
}

/** --projection-matrix or --geometry-from: the whole view, refusing the flags that set a view by parts. */
itk::DRRProjectionGeometry::Pointer
MakeWholeView(const Options & options)
{
  const bool               matrix = !options.projectionMatrixFile.empty();
  const bool               localizer = !options.geometryFrom.empty();
  const std::string        whole = matrix ? "--projection-matrix" : "--geometry-from";
  std::vector<std::string> conflicting = ViewFlagsGiven(options);
  if (matrix && localizer)
  {
    conflicting.push_back("--geometry-from");
  }
  if (localizer && (options.detectorSize || options.detectorSpacing))
  {
    conflicting.push_back("--size/--spacing");
  }
  if (!conflicting.empty())
  {
    throw UsageError(whole + " gives the whole view: it cannot be combined with " + JoinWords(conflicting, ", "));
  }
  return matrix ? MakeGeometryFromMatrix(options) : ReadLocalizerView(options.geometryFrom).Geometry;
}

/** Layer 1: the defaults. */
itk::DRRProjectionGeometry::Pointer
DefaultView(const itk::ImageBase<3> * volume)
{
  auto geometry = itk::DRRProjectionGeometry::New();
  // Gantry 0 as SetGantryAngleInDegrees() gives it, the normal (1, -0, 0), not the geometry's default (1, 0, 0): the
  // view a sweep's row at gantry 0 gives, to the sign of a zero.
  geometry->SetGantryAngleInDegrees(0.0);
  geometry->SetDetectorSize({ { DefaultDetectorPixels, DefaultDetectorPixels } });
  geometry->SetDetectorSpacing(itk::Vector<double, 2>(DefaultDetectorSpacing));
  // Default isocenter: the centre of the volume's bounding box (voxel centres); the room origin before the load.
  if (volume)
  {
    geometry->SetIsocenterToImageCenter(volume);
  }
  return geometry;
}

/** Layer 3: the flags over the view. */
void
ApplyFlags(const Options & options, itk::DRRProjectionGeometry * geometry)
{
  if (options.projection)
  {
    geometry->SetProjection(*options.projection);
  }
  if (options.sad)
  {
    geometry->SetSourceToIsocenterDistance(*options.sad);
  }
  if (options.sid)
  {
    geometry->SetSourceToDetectorDistance(*options.sid);
  }
  if (options.gantryDegrees)
  {
    geometry->SetGantryAngleInDegrees(*options.gantryDegrees);
  }
  if (options.normal)
  {
    geometry->SetNormal(ToVector(*options.normal));
  }
  if (options.viewUp)
  {
    geometry->SetViewUp(ToVector(*options.viewUp));
  }
  if (options.isocenter)
  {
    geometry->SetIsocenter(ToPoint(*options.isocenter));
  }
  if (options.detectorSize)
  {
    geometry->SetDetectorSize({ { static_cast<itk::SizeValueType>((*options.detectorSize)[0]),
                                  static_cast<itk::SizeValueType>((*options.detectorSize)[1]) } });
  }
  if (options.detectorSpacing)
  {
    geometry->SetDetectorSpacing(ToVector(*options.detectorSpacing));
  }
  if (options.detectorOffset)
  {
    geometry->SetDetectorOffset(ToVector(*options.detectorOffset));
  }
}

/** Layer 4: the batch row's fields over the view; a row holds no detector size or pitch (ViewsFileColumns()). */
void
ApplyRow(const ViewSpec & row, itk::DRRProjectionGeometry * geometry)
{
  if (row.GantryDegrees)
  {
    geometry->SetGantryAngleInDegrees(*row.GantryDegrees);
  }
  if (row.Normal)
  {
    geometry->SetNormal(ToVector(*row.Normal));
  }
  if (row.ViewUp)
  {
    geometry->SetViewUp(ToVector(*row.ViewUp));
  }
  if (row.Isocenter)
  {
    geometry->SetIsocenter(ToPoint(*row.Isocenter));
  }
  if (row.Sad)
  {
    geometry->SetSourceToIsocenterDistance(*row.Sad);
  }
  if (row.Sid)
  {
    geometry->SetSourceToDetectorDistance(*row.Sid);
  }
  if (row.Offset)
  {
    geometry->SetDetectorOffset(ToVector(*row.Offset));
  }
}

/** The checks every view passes: the geometry's own, and a detector beyond the isocenter. */
void
VerifyView(const itk::DRRProjectionGeometry * geometry)
{
  geometry->VerifyGeometry();
  if (itk::PointBasedDRREnums::HasSource(geometry->GetProjection()) &&
      !(geometry->GetSourceToDetectorDistance() > geometry->GetSourceToIsocenterDistance()))
  {
    // The render keeps what lies between the source and the detector: the volume would be behind it, the image empty.
    std::ostringstream message;
    message << "the detector lies between the source and the isocenter (SID " << geometry->GetSourceToDetectorDistance()
            << " mm <= SAD " << geometry->GetSourceToIsocenterDistance()
            << " mm), so the volume is behind it: give --sid larger than --sad";
    throw UsageError(message.str());
  }
}
} // namespace

itk::DRRProjectionGeometry::Pointer
MakeView(const Options & options, const ViewSpec & row, const itk::ImageBase<3> * volume)
{
  if (row.Whole)
  {
    return row.Whole;
  }
  if (!options.projectionMatrixFile.empty() || !options.geometryFrom.empty())
  {
    return MakeWholeView(options);
  }
  auto geometry = DefaultView(volume);
  if (!options.geometryFile.empty())
  {
    geometry->ReadGeometryFile(options.geometryFile);
  }
  ApplyFlags(options, geometry);
  ApplyRow(row, geometry);
  VerifyView(geometry);
  return geometry;
}

itk::DRRProjectionGeometry::Pointer
MakeGeometry(const Options & options, const itk::ImageBase<3> * volume)
{
  return MakeView(options, ViewSpec{}, volume);
}

double
SweepStartDegrees(const Options & options)
{
  const auto view = MakeGeometry(options, nullptr);
  auto       gantryOnly = itk::DRRProjectionGeometry::New();
  gantryOnly->SetGantryAngleInDegrees(view->GetGantryAngleInDegrees());
  const auto difference = view->GetNormal() - gantryOnly->GetNormal();
  if (difference.GetNorm() > 1e-12)
  {
    throw UsageError("--angles sweeps the gantry from --gantry or the geometry file's gantry; the view's direction "
                     "is a normal (" +
                     (options.normal ? std::string("--nrm") : "nrm in " + options.geometryFile) +
                     "), which a sweep would replace: give the start as gantry, or the views in a --views file");
  }
  return view->GetGantryAngleInDegrees();
}
} // namespace pbdrr
