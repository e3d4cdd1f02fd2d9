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
#include "itkDRRPointProjection.h"
#include "itkDRRPolicies.h"
#include "vnl/vnl_det.h"

#include <algorithm>
#include <limits>

namespace itk
{
DRRPointProjection::DRRPointProjection(const DRRProjectionGeometry & geometry,
                                       const DRRAttenuationVolume &  volume,
                                       const MatrixType &            roomToVolumeMatrix,
                                       const VectorType &            roomToVolumeOffset)
{
  geometry.VerifyGeometry();
  const double determinant = vnl_det(roomToVolumeMatrix.GetVnlMatrix());
  if (!(std::abs(determinant) > 1e-12) || !std::isfinite(determinant))
  {
    itkGenericExceptionMacro(
      "DRRPointProjection: the transform's linear part is singular or not finite (det = " << determinant << ")");
  }
  const double indexDeterminant = vnl_det(volume.GetIndexToPhysicalMatrix().GetVnlMatrix());
  if (!(std::abs(indexDeterminant) > 0.0) || !std::isfinite(indexDeterminant))
  {
    itkGenericExceptionMacro(
      "DRRPointProjection: the volume's direction * spacing matrix is singular (det = " << indexDeterminant << ")");
  }
  m_RoomMassScale = 1.0 / std::abs(determinant);

  // x_room = A^-1 (origin + D S p - b) = IndexToRoom p + IndexToRoomOffset
  const MatrixType volumeToRoom(roomToVolumeMatrix.GetInverse());
  m_IndexToRoom = volumeToRoom * volume.GetIndexToPhysicalMatrix();
  m_IndexToRoomOffset = volumeToRoom * (volume.GetOrigin().GetVectorFromOrigin() - roomToVolumeOffset);
  m_RoomToIndex = MatrixType(m_IndexToRoom.GetInverse());
  m_RoomToIndexOffset = -(m_RoomToIndex * m_IndexToRoomOffset);

  // From the beam's registration (an unregistered enumerator throws rather than falling back to parallel).
  m_Perspective =
    DRRPolicies::Beams::Visit(geometry.GetProjection(), [](auto beam) { return decltype(beam)::HasSource; });
  m_MagnifiesRows =
    DRRPolicies::Beams::Visit(geometry.GetProjection(), [](auto beam) { return decltype(beam)::MagnifiesRows; });
  m_Columns = static_cast<unsigned int>(geometry.GetDetectorSize()[0]);
  m_Rows = static_cast<unsigned int>(geometry.GetDetectorSize()[1]);
  m_SID = geometry.GetSourceToDetectorDistance();
  const double du = geometry.GetDetectorSpacing()[0];
  const double dv = geometry.GetDetectorSpacing()[1];
  m_PixelArea = du * dv;
  m_InverseDU = 1.0 / du;
  m_InverseDV = 1.0 / dv;
  m_SIDOverDU = m_SID / du;
  m_SIDOverDV = m_SID / dv;
  m_ColumnShift = 0.5 * (m_Columns - 1.0) - geometry.GetDetectorOffset()[0] / du;
  m_RowShift = 0.5 * (m_Rows - 1.0) - geometry.GetDetectorOffset()[1] / dv;

  m_Source = geometry.GetSourcePosition();
  m_Normal = geometry.GetNormal();
  m_U = geometry.GetColumnDirection();
  m_V = geometry.GetRowDirection();
  m_PixelOrigin = geometry.GetPixelCenter(0.0, 0.0);
  m_ColumnStep = m_U * du;
  m_RowStep = m_V * dv;

  const VectorType offsetFromSource = m_IndexToRoomOffset - m_Source.GetVectorFromOrigin();
  m_Z0 = -(offsetFromSource * m_Normal);
  m_PU0 = offsetFromSource * m_U;
  m_PV0 = offsetFromSource * m_V;
  for (unsigned int a = 0; a < 3; ++a)
  {
    VectorType column;
    for (unsigned int r = 0; r < 3; ++r)
    {
      column[r] = m_IndexToRoom[r][a];
    }
    m_GZ[a] = -(column * m_Normal);
    m_GU[a] = column * m_U;
    m_GV[a] = column * m_V;
  }

  const double halfWidthU = std::abs(geometry.GetDetectorOffset()[0]) + (0.5 * m_Columns + 1.0) * du;
  const double halfWidthV = std::abs(geometry.GetDetectorOffset()[1]) + (0.5 * m_Rows + 1.0) * dv;
  // A localizer's obliquity is across the fan only.
  const double tanV = m_MagnifiesRows ? halfWidthV / m_SID : 0.0;
  m_MaximumObliquity = std::sqrt(1.0 + (halfWidthU / m_SID) * (halfWidthU / m_SID) + tanV * tanV);
  m_SmallestPositiveDepth = std::numeric_limits<double>::min();
  m_MinimumDepth = m_SmallestPositiveDepth;
}

DRRPointProjection::PointType
DRRPointProjection::IndexToRoom(const double p[3]) const
{
  PointType x;
  for (unsigned int r = 0; r < 3; ++r)
  {
    x[r] =
      m_IndexToRoomOffset[r] + m_IndexToRoom[r][0] * p[0] + m_IndexToRoom[r][1] * p[1] + m_IndexToRoom[r][2] * p[2];
  }
  return x;
}

void
DRRPointProjection::RoomToIndex(const PointType & x, double p[3]) const
{
  for (unsigned int r = 0; r < 3; ++r)
  {
    p[r] =
      m_RoomToIndexOffset[r] + m_RoomToIndex[r][0] * x[0] + m_RoomToIndex[r][1] * x[1] + m_RoomToIndex[r][2] * x[2];
  }
}

void
DRRPointProjection::ComputeDepthRange(const std::array<double, 3> & lower,
                                      const std::array<double, 3> & upper,
                                      double &                      minimumDepth,
                                      double &                      maximumDepth) const
{
  minimumDepth = std::numeric_limits<double>::infinity();
  maximumDepth = -std::numeric_limits<double>::infinity();
  for (unsigned int corner = 0; corner < 8; ++corner)
  {
    double z = m_Z0;
    for (unsigned int a = 0; a < 3; ++a)
    {
      z += m_GZ[a] * ((corner >> a) & 1u ? upper[a] : lower[a]);
    }
    minimumDepth = std::min(minimumDepth, z);
    maximumDepth = std::max(maximumDepth, z);
  }
}

double
DRRPointProjection::GetMaximumObliquity() const
{
  return m_MaximumObliquity;
}

DRRPointProjection::PointType
DRRPointProjection::GetPixelPosition(double column, double row) const
{
  return m_PixelOrigin + m_ColumnStep * column + m_RowStep * row;
}
} // namespace itk
