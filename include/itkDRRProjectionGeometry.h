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
#ifndef itkDRRProjectionGeometry_h
#define itkDRRProjectionGeometry_h

#include "itkDRRCompatibility.h"
#include "itkImageBase.h"
#include "itkMatrix.h"
#include "itkObject.h"
#include "itkObjectFactory.h"
#include "itkPoint.h"
#include "itkVector.h"
#include "itkSize.h"
#include "itkPointBasedDRREnums.h"
#include "PointBasedDRRExport.h"

#include <istream>
#include <string>
#include <vector>

namespace itk
{
/** \class DRRProjectionGeometry
 * \brief The geometry of one radiograph: source, detector plane, pixel grid.
 *
 * The convention is plastimatch's `drr`, so that its users get the same image. All lengths are in mm,
 * angles in degrees, and the world frame is the physical (LPS) frame of the CT volume:
 *
 * - n = (cos g, -sin g, 0) is the unit vector from the isocenter towards the source for gantry angle g
 *   (or is given directly with SetNormal()). Gantry 0 puts the source on +x, gantry 90 on -y (anterior).
 * - u = unit(vup x n) runs along detector columns (increasing column index i);
 *   v = u x n runs along rows (increasing row index j), so row 0 is at the +vup edge.
 * - Source S = isocenter + SAD n. Detector centre C = S - SID n + offset_u u + offset_v v.
 * - Pixel (i, j) centre = C + (i - (cols - 1) / 2) du u + (j - (rows - 1) / 2) dv v.
 * - Perspective integrates from S to the pixel; parallel integrates the whole line through the pixel
 *   along n; a localizer (CT scout) integrates from S moved along v to the pixel's row, to the pixel (a fan across the
 *   columns, parallel along the rows).
 * - ColumnsMirrored counts the columns along -u; a 3 x 4 projection matrix sets the whole view (SetProjectionMatrix()).
 *
 * The 2D output image of a DRR filter has size (cols, rows), spacing (du, dv) and origin
 * (offset_u - (cols - 1) / 2 du, offset_v - (rows - 1) / 2 dv): its physical coordinates are detector-plane
 * coordinates relative to the foot of the normal from the source. A 3D one-slice output is placed in the
 * room: origin at the centre of pixel (0, 0), direction columns (u, v, -n).
 *
 * \image html geometry.svg "The room seen from +z (left) and the detector seen from the source (right)"
 *
 * The explicit form (source, detector centre, column and row unit vectors) is accepted too and converted to
 * the same internal parameters; ReadGeometryFile() reads the `key value...` file format of docs/design.md section 5
 * (`projection`, `sad`, `sid`, `gantry`, `nrm`, `vup`, `isocenter`, `cols`, `rows`, `spacing`, `offset`, `mirror`),
 * which DRRProjectionGeometryFileIO reads and writes.
 *
 * \sa DRRProjectionGeometryFileIO, PointBasedDRRImageFilter, ExactDRRImageFilter, DRRPointProjection
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRProjectionGeometry : public Object
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRProjectionGeometry);

  /** Standard class type aliases. */
  using Self = DRRProjectionGeometry;
  using Superclass = Object;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(DRRProjectionGeometry);

  /** A point of the room (the volume's physical LPS frame), mm. */
  using PointType = Point<double, 3>;
  /** A vector of the room: a direction (unit) or a displacement (mm). */
  using VectorType = Vector<double, 3>;
  /** Detector size in pixels: (cols, rows). */
  using DetectorSizeType = Size<2>;
  /** A detector-plane quantity along (u, v): a pixel spacing or an offset, mm. */
  using DetectorVectorType = Vector<double, 2>;
  /** Perspective or parallel beam. */
  using ProjectionEnum = PointBasedDRREnums::Projection;

  ///@{
  /** Perspective (default) or parallel beam. */
  itkSetEnumMacro(Projection, ProjectionEnum);
  itkGetConstMacro(Projection, ProjectionEnum);
  ///@}

  ///@{
  /** Source to isocenter distance (SAD), mm. Default 1000. */
  itkSetMacro(SourceToIsocenterDistance, double);
  itkGetConstMacro(SourceToIsocenterDistance, double);
  ///@}

  ///@{
  /** Source to detector-plane distance (SID), mm. Default 1500. */
  itkSetMacro(SourceToDetectorDistance, double);
  itkGetConstMacro(SourceToDetectorDistance, double);
  ///@}

  ///@{
  /** Isocenter in the volume's physical frame, mm. Default (0, 0, 0). */
  itkSetMacro(Isocenter, PointType);
  itkGetConstMacro(Isocenter, PointType);
  ///@}

  /** Gantry angle in degrees: sets the normal to (cos g, -sin g, 0). */
  void
  SetGantryAngleInDegrees(double angleInDegrees);
  /** The angle last given to SetGantryAngleInDegrees(), degrees (default 0). SetNormal() and the explicit forms do
   * not change it: GetNormal() is the direction in force. */
  itkGetConstMacro(GantryAngleInDegrees, double);

  /** Unit vector from the isocenter towards the source (normalized on Set; a vector already of unit length to within
   * 4 eps is kept bit for bit). Overrides the gantry angle. */
  void
  SetNormal(const VectorType & normal);
  /** Unit vector from the isocenter towards the source. Default (1, 0, 0) (gantry 0). */
  itkGetConstReferenceMacro(Normal, VectorType);

  ///@{
  /** View-up vector: row 0 of the detector is at its +vup edge. Default (0, 0, 1). */
  itkSetMacro(ViewUp, VectorType);
  itkGetConstReferenceMacro(ViewUp, VectorType);
  ///@}

  ///@{
  /** Number of detector columns and rows (cols, rows). Default 256 x 256. */
  itkSetMacro(DetectorSize, DetectorSizeType);
  itkGetConstReferenceMacro(DetectorSize, DetectorSizeType);
  ///@}

  ///@{
  /** Detector pixel spacing (du along columns, dv along rows), mm. Default 1 x 1. */
  itkSetMacro(DetectorSpacing, DetectorVectorType);
  itkGetConstReferenceMacro(DetectorSpacing, DetectorVectorType);
  ///@}

  ///@{
  /** Offset of the detector centre in the detector plane (along u, along v), mm. Default 0, 0. */
  itkSetMacro(DetectorOffset, DetectorVectorType);
  itkGetConstReferenceMacro(DetectorOffset, DetectorVectorType);
  ///@}

  /** Explicit perspective form: source, detector centre (centre of the pixel grid), and the column (u) and row
   * (v) unit vectors of the detector. Sets the normal, SID, isocenter (the foot of the normal, SAD = SID),
   * view-up (-v) and offsets accordingly. Throws if u and v are not orthogonal, or if the source does not lie on the
   * +n side of the detector plane (n = v x u: the source must be in front of the detector as seen with u to the
   * right and v down). */
  void
  SetExplicitPerspectiveGeometry(const PointType &  source,
                                 const PointType &  detectorCenter,
                                 const VectorType & columnDirection,
                                 const VectorType & rowDirection);

  /** Explicit parallel form: detector centre and the column (u) and row (v) unit vectors; rays run along
   * -n = u x v. */
  void
  SetExplicitParallelGeometry(const PointType &  detectorCenter,
                              const VectorType & columnDirection,
                              const VectorType & rowDirection);

  /** Sets the isocenter to ComputeImageCenter(image), mm. Throws if image is null. */
  void
  SetIsocenterToImageCenter(const ImageBase<3> * image);

  /** The centre of an image's largest possible region, mm: the centre of the bounding box of its voxel centres,
   * the physical point of continuous index (index + (size - 1) / 2) per axis, honouring origin, spacing and direction.
   * Throws an ExceptionObject if image is null. */
  static PointType
  ComputeImageCenter(const ImageBase<3> * image);

  /** Reads a geometry file: one `key value...` per line, `#` starts a comment. Keys given override the current
   * values; unknown keys, missing or non-numeric values throw an ExceptionObject naming the line. Calls
   * DRRProjectionGeometryFileIO::Read(), which also writes the format. */
  void
  ReadGeometryFile(const std::string & fileName);

  /** Reads the geometry-file format from a stream, as ReadGeometryFile() does for a file (which calls this): each
   * line is given to ParseGeometryLine(), errors name `sourceName:line: ` (or `line N: ` without a source name).
   * Lines before an erroneous one are applied. Calls DRRProjectionGeometryFileIO::ReadFromStream(). */
  void
  ReadGeometry(std::istream & stream, const std::string & sourceName = "");

  /** Parses one geometry-file line (without the trailing newline). Throws on error. Calls
   * DRRProjectionGeometryFileIO::ParseLine(). */
  void
  ParseGeometryLine(const std::string & line, const std::string & where = "");

  /** Throws an ExceptionObject naming the first problem: non-positive SAD, SID or pixel size, zero detector
   * size, non-finite values, a view-up parallel to the normal. */
  void
  VerifyGeometry() const;

  ///@{
  /** Mirrored columns: column index increases along -unit(vup x n) instead (rows unchanged), so that the source sees
   * the detector's columns run right to left: a radiograph shown as seen from behind the detector, or a projection
   * matrix whose pixel axes are left-handed (SetProjectionMatrix()). Default off (plastimatch's convention). */
  itkSetMacro(ColumnsMirrored, bool);
  itkGetConstMacro(ColumnsMirrored, bool);
  itkBooleanMacro(ColumnsMirrored);
  ///@}
  /** Unit column direction u = unit(vup x n) (mirrored: its opposite): increasing column index. Derived, like the
   * quantities below: valid after VerifyGeometry(). */
  VectorType
  GetColumnDirection() const;
  /** Unit row direction v = unit(vup x n) x n: increasing row index, away from the +vup edge (mirrored or not). */
  VectorType
  GetRowDirection() const;
  /** Source S = isocenter + SAD n, mm (a parallel beam has no source: this point still places the detector plane,
   * SID along -n from it). */
  PointType
  GetSourcePosition() const;
  /** Foot of the normal from the source on the detector plane (S - SID n, mm): the origin of detector (u, v)
   * coordinates. */
  PointType
  GetDetectorPlaneOrigin() const;
  /** Centre of the pixel grid C = S - SID n + offset_u u + offset_v v, mm. */
  PointType
  GetDetectorCenter() const;
  /** Centre of pixel (column i, row j) in world coordinates, mm. Fractional indices are allowed. */
  PointType
  GetPixelCenter(double column, double row) const;
  /** Where the ray through detector point (column, row) (fractional allowed) starts, mm: the source (perspective); the
   * source carried along the rows to the point's row (localizer); for a parallel beam, the point 2 SID (at least 10 m)
   * along n from the detector point, the line's far end on the source side. The ray ends at GetPixelCenter(). */
  PointType
  GetRayStart(double column, double row) const;
  /** Detector-plane coordinates (along u, along v, mm) of the centre of pixel (0, 0): the 2D output origin. */
  DetectorVectorType
  GetDetectorOrigin2D() const;

  /** A 3 x 4 projection matrix: homogeneous room point (mm) to homogeneous pixel (column, row, 1). */
  using ProjectionMatrixType = Matrix<double, 3, 4>;
  /** The 3 x 4 projection matrix P of the view: a room point X (mm, homogeneous [X; 1]) projects to the pixel
   * (column, row) = (p0 / p2, p1 / p2) with p = P [X; 1], pixel indices as the output's (centre of pixel 0 at 0).
   * Perspective: a pinhole camera, p2 the depth from the source along -n (mm, positive in front of it). Parallel: an
   * affine camera, last row [0 0 0 1]. Valid after VerifyGeometry(); written beside every pbdrr image. Throws for a
   * beam that has none (HasProjectionMatrix()). */
  ProjectionMatrixType
  GetProjectionMatrix() const;
  /** True if the beam is a pinhole or an affine camera (perspective, parallel); a localizer is neither. */
  bool
  HasProjectionMatrix() const;
  /** Sets the view from a 3 x 4 projection matrix and the detector size (cols, rows): pixel (column, row) = (p0 / p2,
   * p1 / p2), p = P [X; 1], X a room point in mm, pixel indices as the output's (centre of pixel 0 at 0).
   *
   * A pinhole P (its left 3 x 3 block M invertible) is K [R | t] with K = [fx s cx; 0 fy cy; 0 0 1]: the source is P's
   * null vector -M^-1 p4, the normal -r3, the principal point (cx, cy) the foot of the normal, and the focal lengths
   * fx, fy (pixels) give SID = fx du and dv = SID / fy, du being the column spacing in force (default 1 mm). The rays'
   * directions do not depend on du, but they end at the detector plane: give the detector's real pitch, or one that
   * puts the plane beyond the volume (pbdrr refuses a pitch that does not). P's sign must make p2 positive in front of
   * the source (as GetProjectionMatrix() writes it, and as K [R | t] with positive focal lengths does); R of
   * determinant -1 (left-handed pixel axes) sets ColumnsMirrored. The rest is the explicit form's: SAD = SID, the
   * isocenter at the foot of the normal. An affine P (third row 0 0 0 p23) is a parallel beam: its first two rows are u
   * / du and v / dv.
   *
   * Throws an ExceptionObject, changing nothing, for a non-finite or singular P, a skewed pixel grid (|s| > 1e-6 fx;
   * affine: u, v not orthogonal), or a zero detector size. */
  void
  SetProjectionMatrix(const ProjectionMatrixType & matrix, const DetectorSizeType & detectorSize);

protected:
  DRRProjectionGeometry();
  ~DRRProjectionGeometry() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  ProjectionEnum     m_Projection{ ProjectionEnum::Perspective };
  double             m_SourceToIsocenterDistance{ 1000.0 };
  double             m_SourceToDetectorDistance{ 1500.0 };
  PointType          m_Isocenter;
  double             m_GantryAngleInDegrees{ 0.0 };
  VectorType         m_Normal;
  VectorType         m_ViewUp;
  DetectorSizeType   m_DetectorSize;
  DetectorVectorType m_DetectorSpacing;
  DetectorVectorType m_DetectorOffset;
  bool               m_ColumnsMirrored{ false };
};
} // namespace itk

#endif
