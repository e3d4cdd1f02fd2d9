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
#ifndef itkDRRPointProjection_h
#define itkDRRPointProjection_h

#include "itkDRRAttenuationVolume.h"
#include "itkDRRCompilerSupport.h"
#include "itkDRRProjectionGeometry.h"
#include "PointBasedDRRExport.h"

#include <array>
#include <cmath>
#include <limits>
#include <type_traits>

namespace itk
{
/** \class DRRPointProjection
 * \brief Everything one render needs to map a continuous voxel index to the detector, precomputed.
 *
 * The room-to-volume map (an optional linear itk::Transform, as in ITK registration: it maps a room point to the
 * volume's physical frame) and the volume's index-to-physical map are folded into one affine map from continuous
 * index to room coordinates. From it, for a point p (continuous index):
 *
 *   depth z = (x(p) - S) . (-n)      (mm, from the source along the detector normal; perspective)
 *   pu, pv  = (x(p) - S) . u, . v    (mm)
 *   column  = SID pu / z / du + c0    (perspective, localizer) or pu / du + c0 (parallel), c0 = (cols-1)/2 -
 * offset_u/du row     = SID pv / z / dv + r0    (perspective) or pv / dv + r0 (localizer, parallel) weight  = (SID /
 * z)^2 sqrt(1 + (pu/z)^2 + (pv/z)^2)   (perspective), (SID / z) sqrt(1 + (pu/z)^2) (localizer), 1 (parallel)
 *
 * which are affine in p up to one division. A perspective or localizer point counts only for 0 < z <= SID (between
 * source and detector plane); points nearer the source than GetMinimumDepth() are dropped (DRRPointRenderer sets that
 * depth when the volume comes so near the source that its fixed-point sums could overflow, and reports it in
 * DRRPointRenderer::Result::MinimumDepth).
 *
 * \sa DRRProjectionGeometry, DRRPointRenderer
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRPointProjection
{
public:
  /** A 3 x 3 matrix (of the room-to-volume transform, and of continuous index to room). */
  using MatrixType = DRRAttenuationVolume::MatrixType;
  /** A room vector: a direction (unit) or a displacement (mm). */
  using VectorType = DRRProjectionGeometry::VectorType;
  /** A room point, mm. */
  using PointType = DRRProjectionGeometry::PointType;

  /** Builds the mapping. roomToVolumeMatrix/Offset: the linear transform x_volume = A x_room + b (identity when
   * no transform is set). Throws if A is singular. */
  DRRPointProjection(const DRRProjectionGeometry & geometry,
                     const DRRAttenuationVolume &  volume,
                     const MatrixType &            roomToVolumeMatrix,
                     const VectorType &            roomToVolumeOffset);

  /** True for a beam whose rays start at a source (perspective, localizer), false for a parallel one. */
  bool
  IsPerspective() const
  {
    return m_Perspective;
  }

  /** True when rows are magnified as columns are (a cone: perspective); false for a localizer (a fan across, parallel
   * along the rows: its source moves with the row) and for a parallel beam. */
  bool
  MagnifiesRows() const
  {
    return m_MagnifiesRows;
  }

  /** A bound of the weight of every point at depth >= depth (mm) that lands on the detector (widened by a pixel):
   * (SID / depth)^2 times the largest obliquity for a cone, SID / depth times it for a localizer. */
  double
  GetWeightBound(double depth) const
  {
    const double magnification = m_SID / depth;
    return (m_MagnifiesRows ? magnification * magnification : magnification) * m_MaximumObliquity;
  }

  /** The depth (mm) below which a point's weight can exceed weight: the inverse of GetWeightBound(). */
  double
  GetDepthOfWeight(double weight) const
  {
    const double ratio = m_MaximumObliquity / weight;
    return m_SID * (m_MagnifiesRows ? std::sqrt(ratio) : ratio);
  }

  /** Projects n points given as continuous voxel indices (x, y, z): column and row are continuous pixel indices
   * (pixel centres at integers), weight the perspective weight (1 for parallel). A point that does not count (behind
   * the source, beyond the detector plane, or nearer the source than the minimum depth) gets weight 0 and column -4,
   * off the detector for every splat. Branch-free, so that the loop vectorizes.
   *
   * TReal is double for a render that draws its points, float for the render of a kept cloud (whose points are floats
   * already): twice the lanes, and single-precision division and square root are several times cheaper than double.
   * In float, the column is off by at most about 1e-5 pixels and the weight by a relative 1e-7: far below the Monte
   * Carlo noise. Only correctly rounded operations, so every instruction set gives the same bits. */
  template <typename TReal>
  void
  ProjectBatch(size_t                         n,
               const TReal * const            x,
               const TReal * const            y,
               const TReal * const            z,
               TReal * PointBasedDRR_RESTRICT column,
               TReal * PointBasedDRR_RESTRICT row,
               TReal * PointBasedDRR_RESTRICT weight) const
  {
    static_assert(std::is_same<TReal, double>::value || std::is_same<TReal, float>::value, "double or float");
    // Locals, so that the compiler knows the outputs do not alias the parameters (and keeps them in registers); in
    // the precision of the points (a conversion that changes nothing in double).
    const TReal pu0 = static_cast<TReal>(m_PU0), gu0 = static_cast<TReal>(m_GU[0]), gu1 = static_cast<TReal>(m_GU[1]),
                gu2 = static_cast<TReal>(m_GU[2]);
    const TReal pv0 = static_cast<TReal>(m_PV0), gv0 = static_cast<TReal>(m_GV[0]), gv1 = static_cast<TReal>(m_GV[1]),
                gv2 = static_cast<TReal>(m_GV[2]);
    const TReal z0 = static_cast<TReal>(m_Z0), gz0 = static_cast<TReal>(m_GZ[0]), gz1 = static_cast<TReal>(m_GZ[1]),
                gz2 = static_cast<TReal>(m_GZ[2]);
    const TReal columnShift = static_cast<TReal>(m_ColumnShift), rowShift = static_cast<TReal>(m_RowShift);
    const TReal one = 1, offDetector = -4, zero = 0;
    if (!m_Perspective)
    {
      const TReal inverseDU = static_cast<TReal>(m_InverseDU), inverseDV = static_cast<TReal>(m_InverseDV);
      for (size_t i = 0; i < n; ++i)
      {
        column[i] = (pu0 + gu0 * x[i] + gu1 * y[i] + gu2 * z[i]) * inverseDU + columnShift;
        row[i] = (pv0 + gv0 * x[i] + gv1 * y[i] + gv2 * z[i]) * inverseDV + rowShift;
        weight[i] = one;
      }
      return;
    }
    const TReal sid = static_cast<TReal>(m_SID), sidOverDU = static_cast<TReal>(m_SIDOverDU),
                sidOverDV = static_cast<TReal>(m_SIDOverDV);
    // Rounded up, so that no point nearer than the minimum depth counts: its weight would exceed the bound the
    // fixed-point scale was chosen for (in double, exact already).
    TReal minimumDepth = static_cast<TReal>(m_MinimumDepth);
    minimumDepth = minimumDepth < m_MinimumDepth ? std::nextafter(minimumDepth, std::numeric_limits<TReal>::infinity())
                                                 : minimumDepth;
    if (!m_MagnifiesRows)
    {
      // A localizer: a fan across (columns), parallel along (rows); weight sqrt(SID^2 + u^2) / z.
      const TReal inverseDV = static_cast<TReal>(m_InverseDV);
      for (size_t i = 0; i < n; ++i)
      {
        const TReal pu = pu0 + gu0 * x[i] + gu1 * y[i] + gu2 * z[i];
        const TReal pv = pv0 + gv0 * x[i] + gv1 * y[i] + gv2 * z[i];
        const TReal depth = z0 + gz0 * x[i] + gz1 * y[i] + gz2 * z[i];
        const bool  counts = (depth >= minimumDepth) & (depth <= sid);
        const TReal inverseZ = one / depth;
        const TReal tu = pu * inverseZ;
        column[i] = counts ? tu * sidOverDU + columnShift : offDetector;
        row[i] = pv * inverseDV + rowShift;
        weight[i] = counts ? sid * inverseZ * std::sqrt(one + tu * tu) : zero;
      }
      return;
    }
    for (size_t i = 0; i < n; ++i)
    {
      const TReal pu = pu0 + gu0 * x[i] + gu1 * y[i] + gu2 * z[i];
      const TReal pv = pv0 + gv0 * x[i] + gv1 * y[i] + gv2 * z[i];
      const TReal depth = z0 + gz0 * x[i] + gz1 * y[i] + gz2 * z[i];
      // No branch (& not &&, every operation unconditional, a select at the end), so that the loop vectorizes.
      const bool  counts = (depth >= minimumDepth) & (depth <= sid);
      const TReal inverseZ = one / depth;
      const TReal tu = pu * inverseZ;
      const TReal tv = pv * inverseZ;
      const TReal magnification = sid * inverseZ;
      column[i] = counts ? tu * sidOverDU + columnShift : offDetector;
      row[i] = tv * sidOverDV + rowShift;
      weight[i] = counts ? magnification * magnification * std::sqrt(one + tu * tu + tv * tv) : zero;
    }
  }

  /** Where a point falls on the detector plane (continuous pixel indices) and its depth (mm from the source along the
   * normal; parallel: from the source plane), with no depth limit. Perspective columns and rows mean nothing for
   * depth <= 0. */
  void
  ProjectToDetectorPlane(const double p[3], double & column, double & row, double & depth) const
  {
    const double pu = m_PU0 + m_GU[0] * p[0] + m_GU[1] * p[1] + m_GU[2] * p[2];
    const double pv = m_PV0 + m_GV[0] * p[0] + m_GV[1] * p[1] + m_GV[2] * p[2];
    depth = m_Z0 + m_GZ[0] * p[0] + m_GZ[1] * p[1] + m_GZ[2] * p[2];
    if (!m_Perspective)
    {
      column = pu * m_InverseDU + m_ColumnShift;
      row = pv * m_InverseDV + m_RowShift;
      return;
    }
    column = pu / depth * m_SIDOverDU + m_ColumnShift;
    row = m_MagnifiesRows ? pv / depth * m_SIDOverDV + m_RowShift : pv * m_InverseDV + m_RowShift;
  }

  /** Continuous voxel index -> room point (mm), through the volume's geometry and the transform. */
  PointType
  IndexToRoom(const double p[3]) const;
  /** Room point (mm) -> continuous voxel index: the inverse of IndexToRoom(). */
  void
  RoomToIndex(const PointType & x, double p[3]) const;

  /** Room volume per volume-frame volume (1 / |det A|): the attenuation mass seen in the room is M times this. */
  double
  GetRoomMassScale() const
  {
    return m_RoomMassScale;
  }

  /** Depth range of the continuous-index box [lower, upper]^3 (per axis) in the room, mm from the source. */
  void
  ComputeDepthRange(const std::array<double, 3> & lower,
                    const std::array<double, 3> & upper,
                    double &                      minimumDepth,
                    double &                      maximumDepth) const;

  /** The largest obliquity factor sqrt(1 + tan^2) of the perspective weight over the detector widened by one pixel
   * (tan: the ray's angle to the normal), a bound of that factor for every point that lands on the detector. */
  double
  GetMaximumObliquity() const;

  /** Points at depth below this (mm) are dropped. Default: 0 (only points behind the source). */
  void
  SetMinimumDepth(double depth)
  {
    m_MinimumDepth = depth > 0.0 ? depth : m_SmallestPositiveDepth;
  }
  /** Depth below which perspective points are dropped, mm from the source (default: any positive depth counts). */
  double
  GetMinimumDepth() const
  {
    return m_MinimumDepth;
  }

  /** Source to detector-plane distance (SID), mm. */
  double
  GetSourceToDetectorDistance() const
  {
    return m_SID;
  }
  /** Source position S in the room, mm. */
  const PointType &
  GetSource() const
  {
    return m_Source;
  }
  /** Unit normal n, from the detector towards the source. */
  const VectorType &
  GetNormal() const
  {
    return m_Normal;
  }
  /** Unit column direction u of the detector. */
  const VectorType &
  GetColumnDirection() const
  {
    return m_U;
  }
  /** Unit row direction v of the detector. */
  const VectorType &
  GetRowDirection() const
  {
    return m_V;
  }
  /** Room position of pixel (column, row) (fractional allowed) on the detector plane. */
  PointType
  GetPixelPosition(double column, double row) const;

  /** Number of detector columns (cols). */
  unsigned int
  GetNumberOfColumns() const
  {
    return m_Columns;
  }
  /** Number of detector rows (rows). */
  unsigned int
  GetNumberOfRows() const
  {
    return m_Rows;
  }
  /** Pixel area, mm^2. */
  double
  GetPixelArea() const
  {
    return m_PixelArea;
  }

private:
  /** The backward pass differentiates the projection above point by point, from its coefficients. */
  friend class DRRPointPoseGradient;

  bool         m_Perspective;
  bool         m_MagnifiesRows;
  unsigned int m_Columns;
  unsigned int m_Rows;
  double       m_SID;
  double       m_PixelArea;
  double       m_InverseDU;
  double       m_InverseDV;
  double       m_SIDOverDU;
  double       m_SIDOverDV;
  double       m_ColumnShift;
  double       m_RowShift;
  double       m_Z0;
  double       m_GZ[3];
  double       m_PU0;
  double       m_GU[3];
  double       m_PV0;
  double       m_GV[3];
  double       m_RoomMassScale;
  double       m_MinimumDepth;
  double       m_SmallestPositiveDepth;
  double       m_MaximumObliquity;
  PointType    m_Source;
  PointType    m_PixelOrigin;
  VectorType   m_Normal;
  VectorType   m_U;
  VectorType   m_V;
  VectorType   m_ColumnStep;
  VectorType   m_RowStep;
  MatrixType   m_IndexToRoom;
  VectorType   m_IndexToRoomOffset;
  MatrixType   m_RoomToIndex;
  VectorType   m_RoomToIndexOffset;
};
} // namespace itk

#endif
