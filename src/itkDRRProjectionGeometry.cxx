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
#include "itkDRRProjectionGeometry.h"
#include "itkDRRPolicies.h"
#include "itkDRRProjectionGeometryFileIO.h"
#include "itkContinuousIndex.h"
#include "itkMath.h"
#include "vnl/vnl_det.h"

#include <cmath>
#include <limits>

namespace itk
{
namespace
{
constexpr double orthogonalityTolerance = 1e-6;

DRRProjectionGeometry::VectorType
Cross(const DRRProjectionGeometry::VectorType & a, const DRRProjectionGeometry::VectorType & b)
{
  DRRProjectionGeometry::VectorType c;
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
  return c;
}

bool
AllFinite(const DRRProjectionGeometry::VectorType & v)
{
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

[[noreturn]] void
ThrowGeometryError(const std::string & message)
{
  ExceptionObject e(__FILE__, __LINE__, "DRRProjectionGeometry: " + message, ITK_LOCATION);
  throw e;
}

/** Unit column and row directions and the normal n = v x u of an explicit detector (v = u x n and u = vup x n with
 * vup = -v give n = v x u). Throws, changing nothing, if the directions are zero, non-finite or not orthogonal. */
void
DetectorFrame(const DRRProjectionGeometry::VectorType & columnDirection,
              const DRRProjectionGeometry::VectorType & rowDirection,
              DRRProjectionGeometry::VectorType &       u,
              DRRProjectionGeometry::VectorType &       v,
              DRRProjectionGeometry::VectorType &       n)
{
  const double uNorm = columnDirection.GetNorm();
  const double vNorm = rowDirection.GetNorm();
  if (!(uNorm > 0.0) || !(vNorm > 0.0) || !AllFinite(columnDirection) || !AllFinite(rowDirection))
  {
    ThrowGeometryError("the detector column and row directions must be finite, non-zero vectors");
  }
  u = columnDirection / uNorm;
  v = rowDirection / vNorm;
  if (std::abs(u * v) > orthogonalityTolerance)
  {
    ThrowGeometryError("the detector column and row directions are not orthogonal");
  }
  n = Cross(v, u);
}

/** unit(vup x n): the column direction of plastimatch's convention. */
DRRProjectionGeometry::VectorType
UnmirroredColumnDirection(const DRRProjectionGeometry::VectorType & viewUp,
                          const DRRProjectionGeometry::VectorType & normal)
{
  const DRRProjectionGeometry::VectorType u = Cross(viewUp, normal);
  const double                            norm = u.GetNorm();
  return norm > 0.0 ? DRRProjectionGeometry::VectorType(u / norm) : u;
}

template <typename TMatrix>
DRRProjectionGeometry::VectorType
MatrixRow(const TMatrix & matrix, unsigned int row)
{
  DRRProjectionGeometry::VectorType v;
  for (unsigned int a = 0; a < 3; ++a)
  {
    v[a] = matrix[row][a];
  }
  return v;
}
} // namespace

DRRProjectionGeometry::DRRProjectionGeometry()
{
  m_Isocenter.Fill(0.0);
  m_Normal[0] = 1.0;
  m_Normal[1] = 0.0;
  m_Normal[2] = 0.0;
  m_ViewUp[0] = 0.0;
  m_ViewUp[1] = 0.0;
  m_ViewUp[2] = 1.0;
  m_DetectorSize.Fill(256);
  m_DetectorSpacing.Fill(1.0);
  m_DetectorOffset.Fill(0.0);
}

void
DRRProjectionGeometry::SetGantryAngleInDegrees(double angleInDegrees)
{
  const double radians = angleInDegrees * Math::pi / 180.0;
  VectorType   normal;
  normal[0] = std::cos(radians);
  normal[1] = -std::sin(radians);
  normal[2] = 0.0;
  m_GantryAngleInDegrees = angleInDegrees;
  m_Normal = normal;
  this->Modified();
}

void
DRRProjectionGeometry::SetNormal(const VectorType & normal)
{
  const double length = normal.GetNorm();
  if (!(length > 0.0) || !AllFinite(normal))
  {
    ThrowGeometryError("the normal (nrm) must be a finite, non-zero vector");
  }
  // A unit vector to rounding (as normal / length is: within 1.5 eps) is kept as given, so that setting the normal in
  // force again (a geometry file written by DRRProjectionGeometryFileIO) changes no bit: dividing a third of them
  // by their computed length again would move them by an ulp.
  constexpr double unitTolerance = 4.0 * std::numeric_limits<double>::epsilon();
  m_Normal = std::abs(length - 1.0) <= unitTolerance ? normal : normal / length;
  this->Modified();
}

void
DRRProjectionGeometry::SetExplicitPerspectiveGeometry(const PointType &  source,
                                                      const PointType &  detectorCenter,
                                                      const VectorType & columnDirection,
                                                      const VectorType & rowDirection)
{
  VectorType u, v, n;
  DetectorFrame(columnDirection, rowDirection, u, v, n);
  const double sid = (source - detectorCenter) * n;
  if (!(sid > 0.0) || !AllFinite(source.GetVectorFromOrigin()))
  {
    ThrowGeometryError("the source must lie on the +n side of the detector plane (n = row x column direction)");
  }
  const PointType foot = source - n * sid;
  m_Projection = ProjectionEnum::Perspective;
  m_Normal = n;
  m_ViewUp = -v;
  m_SourceToDetectorDistance = sid;
  m_SourceToIsocenterDistance = sid;
  m_Isocenter = foot;
  m_DetectorOffset[0] = (detectorCenter - foot) * u;
  m_DetectorOffset[1] = (detectorCenter - foot) * v;
  this->Modified();
}

void
DRRProjectionGeometry::SetExplicitParallelGeometry(const PointType &  detectorCenter,
                                                   const VectorType & columnDirection,
                                                   const VectorType & rowDirection)
{
  VectorType u, v, n;
  DetectorFrame(columnDirection, rowDirection, u, v, n);
  m_Projection = ProjectionEnum::Parallel;
  m_Normal = n;
  m_ViewUp = -v;
  // Place the source-side reference point so that the foot of the normal is the detector centre.
  m_Isocenter = detectorCenter;
  m_SourceToIsocenterDistance = m_SourceToDetectorDistance;
  m_DetectorOffset.Fill(0.0);
  this->Modified();
}

DRRProjectionGeometry::VectorType
DRRProjectionGeometry::GetColumnDirection() const
{
  const VectorType u = UnmirroredColumnDirection(m_ViewUp, m_Normal);
  return m_ColumnsMirrored ? VectorType(-u) : u;
}

DRRProjectionGeometry::VectorType
DRRProjectionGeometry::GetRowDirection() const
{
  return Cross(UnmirroredColumnDirection(m_ViewUp, m_Normal), m_Normal);
}

DRRProjectionGeometry::PointType
DRRProjectionGeometry::GetSourcePosition() const
{
  return m_Isocenter + m_Normal * m_SourceToIsocenterDistance;
}

DRRProjectionGeometry::PointType
DRRProjectionGeometry::GetDetectorPlaneOrigin() const
{
  return this->GetSourcePosition() - m_Normal * m_SourceToDetectorDistance;
}

DRRProjectionGeometry::PointType
DRRProjectionGeometry::GetDetectorCenter() const
{
  return this->GetDetectorPlaneOrigin() + this->GetColumnDirection() * m_DetectorOffset[0] +
         this->GetRowDirection() * m_DetectorOffset[1];
}

DRRProjectionGeometry::PointType
DRRProjectionGeometry::GetPixelCenter(double column, double row) const
{
  const double du = (column - 0.5 * (static_cast<double>(m_DetectorSize[0]) - 1.0)) * m_DetectorSpacing[0];
  const double dv = (row - 0.5 * (static_cast<double>(m_DetectorSize[1]) - 1.0)) * m_DetectorSpacing[1];
  return this->GetDetectorCenter() + this->GetColumnDirection() * du + this->GetRowDirection() * dv;
}

DRRProjectionGeometry::PointType
DRRProjectionGeometry::GetRayStart(double column, double row) const
{
  const PointType pixel = this->GetPixelCenter(column, row);
  switch (m_Projection)
  {
    case ProjectionEnum::Perspective:
      return this->GetSourcePosition();
    case ProjectionEnum::Localizer:
    {
      const PointType  source = this->GetSourcePosition();
      const VectorType v = this->GetRowDirection();
      return source + v * ((pixel - source) * v);
    }
    default:
      return pixel + m_Normal * std::max(2.0 * m_SourceToDetectorDistance, 1e4);
  }
}

bool
DRRProjectionGeometry::HasProjectionMatrix() const
{
  return m_Projection != ProjectionEnum::Localizer;
}

void
DRRProjectionGeometry::SetProjectionMatrix(const ProjectionMatrixType & matrix, const DetectorSizeType & detectorSize)
{
  for (unsigned int r = 0; r < 3; ++r)
  {
    for (unsigned int c = 0; c < 4; ++c)
    {
      if (!std::isfinite(matrix[r][c]))
      {
        ThrowGeometryError("the projection matrix has a non-finite entry");
      }
    }
  }
  if (detectorSize[0] == 0 || detectorSize[1] == 0)
  {
    ThrowGeometryError("a projection matrix needs the detector's size (cols, rows), got zero");
  }
  const VectorType m1 = MatrixRow(matrix, 0), m2 = MatrixRow(matrix, 1), m3 = MatrixRow(matrix, 2);
  const double     scale = std::max(m1.GetNorm(), m2.GetNorm());
  const double     centreColumn = 0.5 * (static_cast<double>(detectorSize[0]) - 1.0);
  const double     centreRow = 0.5 * (static_cast<double>(detectorSize[1]) - 1.0);
  if (!(scale > 0.0))
  {
    ThrowGeometryError("the projection matrix is singular: its first two rows are zero");
  }
  if (!(m3.GetNorm() > 1e-12 * scale))
  {
    // An affine camera: column = a1 . X + b1, row = a2 . X + b2 once the last row is [0 0 0 1].
    const double w = matrix[2][3];
    if (!(std::abs(w) > 0.0))
    {
      ThrowGeometryError("the projection matrix is singular: its last row is zero");
    }
    const VectorType a1 = m1 / w, a2 = m2 / w;
    const double     du = 1.0 / a1.GetNorm(), dv = 1.0 / a2.GetNorm();
    const VectorType u = a1 * du, v = a2 * dv;
    if (!(du > 0.0) || !(dv > 0.0) || !std::isfinite(du) || !std::isfinite(dv))
    {
      ThrowGeometryError("the affine projection matrix is singular: a row of its left block is zero");
    }
    if (std::abs(u * v) > orthogonalityTolerance)
    {
      ThrowGeometryError(
        "the affine projection matrix has a skewed pixel grid (its first two rows are not orthogonal)");
    }
    const PointType centre =
      PointType() + u * ((centreColumn - matrix[0][3] / w) * du) + v * ((centreRow - matrix[1][3] / w) * dv);
    this->SetExplicitParallelGeometry(centre, u, v);
    m_ColumnsMirrored = false;
    m_DetectorSize = detectorSize;
    m_DetectorSpacing[0] = du;
    m_DetectorSpacing[1] = dv;
    return;
  }
  // A pinhole: normalized so that the third row of M is the unit viewing direction r3 (p2 the depth in mm).
  Matrix<double, 3, 3> M;
  VectorType           p4;
  const double         inverseNorm = 1.0 / m3.GetNorm();
  for (unsigned int r = 0; r < 3; ++r)
  {
    for (unsigned int a = 0; a < 3; ++a)
    {
      M[r][a] = matrix[r][a] * inverseNorm;
    }
    p4[r] = matrix[r][3] * inverseNorm;
  }
  const double determinant = vnl_det(M.GetVnlMatrix());
  if (!(std::abs(determinant) > 1e-12 * scale * scale * inverseNorm * inverseNorm) || !std::isfinite(determinant))
  {
    ThrowGeometryError("the projection matrix is singular: its left 3 x 3 block has no inverse");
  }
  const VectorType r3 = MatrixRow(M, 2);
  const VectorType q2 = MatrixRow(M, 1);
  const double     cy = q2 * r3;
  VectorType       r2 = q2 - r3 * cy;
  const double     fy = r2.GetNorm();
  r2 /= fy;
  const VectorType q1 = MatrixRow(M, 0);
  const double     cx = q1 * r3;
  const double     skew = (q1 - r3 * cx) * r2;
  VectorType       r1 = q1 - r3 * cx - r2 * skew;
  const double     fx = r1.GetNorm();
  r1 /= fx;
  if (std::abs(skew) > 1e-6 * fx)
  {
    ThrowGeometryError("the projection matrix has a skewed pixel grid (skew " + std::to_string(skew) + " against fx " +
                       std::to_string(fx) + " pixels): not supported");
  }
  const VectorType null = -(Matrix<double, 3, 3>(M.GetInverse()) * p4);
  PointType        source;
  for (unsigned int a = 0; a < 3; ++a)
  {
    source[a] = null[a];
  }
  const double du = m_DetectorSpacing[0];
  const double sid = fx * du;
  m_Projection = ProjectionEnum::Perspective;
  m_ColumnsMirrored = r1 * Cross(r2, r3) < 0.0;
  m_Normal = -r3;
  m_ViewUp = -r2;
  m_SourceToDetectorDistance = sid;
  m_SourceToIsocenterDistance = sid;
  m_Isocenter = source - m_Normal * sid;
  m_DetectorSize = detectorSize;
  m_DetectorSpacing[1] = sid / fy;
  m_DetectorOffset[0] = (centreColumn - cx) * du;
  m_DetectorOffset[1] = (centreRow - cy) * m_DetectorSpacing[1];
  this->Modified();
}

DRRProjectionGeometry::ProjectionMatrixType
DRRProjectionGeometry::GetProjectionMatrix() const
{
  if (!this->HasProjectionMatrix())
  {
    ThrowGeometryError(std::string("a ") + DRRPolicies::Beams::GetName(m_Projection) +
                       " beam has no 3 x 4 projection matrix");
  }
  // column = (u . (Y - O) - offset_u) / du + (cols - 1) / 2 at the detector-plane point Y of X, O the plane's origin;
  // in perspective Y - O = SID / w (X - S) projected on the plane, w = -n . (X - S), so w column is linear in X.
  const VectorType u = this->GetColumnDirection();
  const VectorType v = this->GetRowDirection();
  const double     centreColumn =
    0.5 * (static_cast<double>(m_DetectorSize[0]) - 1.0) - m_DetectorOffset[0] / m_DetectorSpacing[0];
  const double centreRow =
    0.5 * (static_cast<double>(m_DetectorSize[1]) - 1.0) - m_DetectorOffset[1] / m_DetectorSpacing[1];
  const bool           perspective = m_Projection == ProjectionEnum::Perspective;
  const double         scale = perspective ? m_SourceToDetectorDistance : 1.0;
  const PointType      anchor = perspective ? this->GetSourcePosition() : this->GetDetectorPlaneOrigin();
  ProjectionMatrixType matrix;
  for (unsigned int a = 0; a < 3; ++a)
  {
    const double depth = perspective ? -m_Normal[a] : 0.0;
    matrix[0][a] = scale * u[a] / m_DetectorSpacing[0] + centreColumn * depth;
    matrix[1][a] = scale * v[a] / m_DetectorSpacing[1] + centreRow * depth;
    matrix[2][a] = depth;
  }
  for (unsigned int r = 0; r < 3; ++r)
  {
    double constant = 0.0;
    for (unsigned int a = 0; a < 3; ++a)
    {
      constant -= matrix[r][a] * anchor[a];
    }
    matrix[r][3] = constant;
  }
  if (!perspective)
  {
    matrix[0][3] += centreColumn;
    matrix[1][3] += centreRow;
    matrix[2][3] = 1.0;
  }
  return matrix;
}

DRRProjectionGeometry::DetectorVectorType
DRRProjectionGeometry::GetDetectorOrigin2D() const
{
  DetectorVectorType origin;
  for (unsigned int d = 0; d < 2; ++d)
  {
    origin[d] = m_DetectorOffset[d] - 0.5 * (static_cast<double>(m_DetectorSize[d]) - 1.0) * m_DetectorSpacing[d];
  }
  return origin;
}

void
DRRProjectionGeometry::VerifyGeometry() const
{
  // Lengths a radiograph can mean, 1 nm to 10 km: far outside, float images and projections lose all precision.
  constexpr double shortest = 1e-6;
  constexpr double longest = 1e7;
  const auto       outOfRange = [](double length) { return !(std::abs(length) <= longest); };
  if (outOfRange(m_SourceToIsocenterDistance) || outOfRange(m_SourceToDetectorDistance) ||
      outOfRange(m_DetectorOffset[0]) || outOfRange(m_DetectorOffset[1]) || outOfRange(m_Isocenter[0]) ||
      outOfRange(m_Isocenter[1]) || outOfRange(m_Isocenter[2]))
  {
    ThrowGeometryError("SAD, SID, detector offset and isocenter must be within 1e7 mm (10 km)");
  }
  if (static_cast<double>(m_DetectorSize[0]) * static_cast<double>(m_DetectorSize[1]) > 268435456.0)
  {
    ThrowGeometryError("a detector of " + std::to_string(m_DetectorSize[0]) + " x " +
                       std::to_string(m_DetectorSize[1]) + " pixels is more than 2^28 pixels");
  }
  if (DRRPolicies::Beams::Visit(m_Projection, [](auto beam) { return decltype(beam)::HasSource; }))
  {
    if (!(m_SourceToIsocenterDistance > 0.0) || !std::isfinite(m_SourceToIsocenterDistance))
    {
      ThrowGeometryError("the source to isocenter distance (SAD) must be positive and finite, got " +
                         std::to_string(m_SourceToIsocenterDistance) + " mm");
    }
    if (!(m_SourceToDetectorDistance >= shortest) || !std::isfinite(m_SourceToDetectorDistance))
    {
      ThrowGeometryError("the source to detector distance (SID) must be positive, at least 1e-6 mm, got " +
                         std::to_string(m_SourceToDetectorDistance) + " mm");
    }
  }
  else if (!std::isfinite(m_SourceToIsocenterDistance) || !std::isfinite(m_SourceToDetectorDistance))
  {
    ThrowGeometryError("SAD and SID must be finite");
  }
  for (unsigned int d = 0; d < 2; ++d)
  {
    const char * axis = d == 0 ? "column (du)" : "row (dv)";
    if (m_DetectorSize[d] == 0)
    {
      ThrowGeometryError(std::string("the detector has zero ") + (d == 0 ? "columns" : "rows"));
    }
    if (!(m_DetectorSpacing[d] >= shortest && m_DetectorSpacing[d] <= longest))
    {
      ThrowGeometryError(std::string("the detector pixel spacing along the ") + axis +
                         " must be positive, from 1e-6 to 1e7 mm, got " + std::to_string(m_DetectorSpacing[d]) + " mm");
    }
    if (!std::isfinite(m_DetectorOffset[d]))
    {
      ThrowGeometryError("the detector offset must be finite");
    }
  }
  if (!AllFinite(m_Isocenter.GetVectorFromOrigin()))
  {
    ThrowGeometryError("the isocenter must be finite");
  }
  if (!AllFinite(m_Normal) || std::abs(m_Normal.GetNorm() - 1.0) > 1e-9)
  {
    ThrowGeometryError("the normal must be a finite unit vector");
  }
  const double vupNorm = m_ViewUp.GetNorm();
  if (!AllFinite(m_ViewUp) || !(vupNorm > 0.0) || Cross(m_ViewUp / vupNorm, m_Normal).GetNorm() < 1e-6)
  {
    ThrowGeometryError("the view-up vector (vup) is zero or parallel to the normal (nrm): the detector rows and "
                       "columns are undefined");
  }
}

void
DRRProjectionGeometry::ParseGeometryLine(const std::string & line, const std::string & where)
{
  DRRProjectionGeometryFileIO::ParseLine(line, this, where);
}

void
DRRProjectionGeometry::ReadGeometryFile(const std::string & fileName)
{
  const auto io = DRRProjectionGeometryFileIO::New();
  io->SetFileName(fileName);
  io->Read(this);
}

void
DRRProjectionGeometry::ReadGeometry(std::istream & stream, const std::string & sourceName)
{
  DRRProjectionGeometryFileIO::ReadFromStream(stream, this, sourceName);
}

DRRProjectionGeometry::PointType
DRRProjectionGeometry::ComputeImageCenter(const ImageBase<3> * image)
{
  if (image == nullptr)
  {
    ThrowGeometryError("no image given to compute the centre of");
  }
  const auto                 region = image->GetLargestPossibleRegion();
  ContinuousIndex<double, 3> centerIndex;
  for (unsigned int a = 0; a < 3; ++a)
  {
    centerIndex[a] = static_cast<double>(region.GetIndex()[a]) + 0.5 * (static_cast<double>(region.GetSize()[a]) - 1.0);
  }
  PointType center;
  image->TransformContinuousIndexToPhysicalPoint(centerIndex, center);
  return center;
}

void
DRRProjectionGeometry::SetIsocenterToImageCenter(const ImageBase<3> * image)
{
  this->SetIsocenter(ComputeImageCenter(image));
}

void
DRRProjectionGeometry::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "Projection: " << m_Projection << std::endl;
  os << indent << "SourceToIsocenterDistance (mm): " << m_SourceToIsocenterDistance << std::endl;
  os << indent << "SourceToDetectorDistance (mm): " << m_SourceToDetectorDistance << std::endl;
  os << indent << "Isocenter (mm): " << m_Isocenter << std::endl;
  os << indent << "GantryAngleInDegrees: " << m_GantryAngleInDegrees << std::endl;
  os << indent << "Normal: " << m_Normal << std::endl;
  os << indent << "ViewUp: " << m_ViewUp << std::endl;
  os << indent << "DetectorSize (cols, rows): " << m_DetectorSize << std::endl;
  os << indent << "DetectorSpacing (mm): " << m_DetectorSpacing << std::endl;
  os << indent << "DetectorOffset (mm): " << m_DetectorOffset << std::endl;
  os << indent << "ColumnsMirrored: " << (m_ColumnsMirrored ? "On" : "Off") << std::endl;
}
} // namespace itk
