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
#ifndef itkDRRRTKGeometryFileIO_h
#define itkDRRRTKGeometryFileIO_h

#include "itkDRRCompatibility.h"
#include "itkDRRProjectionGeometry.h"
#include "itkMatrix.h"
#include "PointBasedDRRExport.h"

#include <istream>
#include <ostream>
#include <string>
#include <vector>

namespace itk
{
/** \class DRRRTKGeometryFileIO
 * \brief Reads and writes RTK's projection geometry XML (rtk::ThreeDCircularProjectionGeometry, format version 3, as
 * rtksimulatedgeometry writes it): one DRRProjectionGeometry per `Projection` element.
 *
 * RTK describes each view with nine parameters (GantryAngle, OutOfPlaneAngle, InPlaneAngle in degrees;
 * SourceToIsocenterDistance, SourceOffsetX/Y, SourceToDetectorDistance, ProjectionOffsetX/Y in mm) and a 3 x 4
 * `Matrix` from a room point (mm, RTK's isocenter at the room origin) to the detector's physical coordinates (mm).
 * Those coordinates are tied to pixel indices by the projection image's origin, spacing and direction, which the XML
 * does not hold: this class takes them (SetDetectorSize(), SetDetectorSpacing(), SetDetectorOrigin() or a centred
 * origin, SetDetectorDirection()) and maps every view exactly (docs/design.md section 5, "RTK's geometry"): a room
 * point projects to the same detector point in both conventions.
 *
 * Reading follows RTK's reader: element names are compared without case, a value outside a `Projection` is shared by
 * the projections after it, a value inside one carries over to the next ones (RTK never resets them), and each
 * projection's stored `Matrix` must match the one computed from its parameters to 0.001 (RTK's tolerance). It refuses
 * with an ExceptionObject naming the file, the projection (counted from 0) and the element: a file that is not
 * well-formed XML (or is truncated; ITK's DOMNodeXMLReader parses it with expat, and an error names the open element
 * by its path, /RTKThreeDCircularGeometry/Projection[2]/Matrix[1]), another root, a version other than 2 or 3, no
 * projection, a projection without GantryAngle or Matrix, a value that is not a finite number, a negative
 * SourceToDetectorDistance, a SourceToIsocenterDistance that is not positive, parallel and divergent views mixed (as
 * RTK does), a cylindrical detector or a collimation (which DRRProjectionGeometry cannot express).
 * SourceToDetectorDistance 0 is RTK's parallel beam.
 *
 * Writing decomposes each view into RTK's parameters and writes the Matrix as RTK computes it, values shared by all
 * views once (as RTK's writer does), every number with 17 significant digits: the file reads back to the same
 * projection matrices (to rounding). It refuses a localizer beam, and a view whose detector, with the
 * DetectorDirection in force, would have RTK's axes left-handed (a DRR image not mirrored is RTK's with its rows
 * reversed: SetColumnsMirrored(true) on the geometry, or a DetectorDirection of diag(1, -1)).
 *
 * \sa DRRProjectionGeometry, DRRProjectionMatrixFileIO
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRRTKGeometryFileIO : public Object
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRRTKGeometryFileIO);

  /** Standard class type aliases. */
  using Self = DRRRTKGeometryFileIO;
  using Superclass = Object;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(DRRRTKGeometryFileIO);

  /** The views read. */
  using GeometryListType = std::vector<DRRProjectionGeometry::Pointer>;
  /** The views written. */
  using ConstGeometryListType = std::vector<DRRProjectionGeometry::ConstPointer>;
  /** Detector size in pixels (columns, rows). */
  using DetectorSizeType = DRRProjectionGeometry::DetectorSizeType;
  /** A detector-plane quantity (column axis, row axis): pixel spacing or origin, mm. */
  using DetectorVectorType = DRRProjectionGeometry::DetectorVectorType;
  /** The 2 x 2 orthogonal direction of RTK's projection image: column k is the detector axis (RTK's x, y) along which
   * pixel index k increases. */
  using DetectorDirectionType = Matrix<double, 2, 2>;
  /** RTK's 3 x 4 matrix: homogeneous room point (mm) to homogeneous detector physical point (mm). */
  using RTKMatrixType = Matrix<double, 3, 4>;

  /** The nine parameters of one RTK view, as in the XML (angles in degrees, lengths in mm). */
  struct ProjectionParameters
  {
    /** GantryAngle: rotation about the room's y axis, degrees. */
    double GantryAngle{ 0.0 };
    /** OutOfPlaneAngle: rotation about the rotated x axis, degrees. */
    double OutOfPlaneAngle{ 0.0 };
    /** InPlaneAngle: rotation about the detector normal, degrees. */
    double InPlaneAngle{ 0.0 };
    /** SourceToIsocenterDistance: the source's coordinate along the detector normal, mm. */
    double SourceToIsocenterDistance{ 0.0 };
    /** SourceOffsetX: the source's coordinate along RTK's detector x axis, mm. */
    double SourceOffsetX{ 0.0 };
    /** SourceOffsetY: the source's coordinate along RTK's detector y axis, mm. */
    double SourceOffsetY{ 0.0 };
    /** SourceToDetectorDistance: source to detector plane along the normal, mm; 0 for a parallel beam. */
    double SourceToDetectorDistance{ 0.0 };
    /** ProjectionOffsetX: the x coordinate of the detector's physical origin (0, 0), mm. */
    double ProjectionOffsetX{ 0.0 };
    /** ProjectionOffsetY: the y coordinate of the detector's physical origin (0, 0), mm. */
    double ProjectionOffsetY{ 0.0 };
  };

  ///@{
  /** The file Read() reads and Write() writes. */
  itkSetStringMacro(FileName);
  itkGetStringMacro(FileName);
  ///@}

  ///@{
  /** Reading: the detector size (columns, rows) given to every view. Default 256 x 256. */
  itkSetMacro(DetectorSize, DetectorSizeType);
  itkGetConstReferenceMacro(DetectorSize, DetectorSizeType);
  ///@}

  ///@{
  /** Reading: the pixel spacing of RTK's projection images (along index 0, index 1), mm, given to every view.
   * Default 1 x 1. */
  itkSetMacro(DetectorSpacing, DetectorVectorType);
  itkGetConstReferenceMacro(DetectorSpacing, DetectorVectorType);
  ///@}

  /** The origin of RTK's projection images: the detector physical coordinates (RTK's x, y, mm) of the centre of pixel
   * (0, 0). Turns DetectorOriginCentered off. */
  void
  SetDetectorOrigin(const DetectorVectorType & origin);
  /** The origin given to SetDetectorOrigin() (in force when DetectorOriginCentered is off). Default (0, 0). */
  itkGetConstReferenceMacro(DetectorOrigin, DetectorVectorType);

  ///@{
  /** On (default): each view's origin centres its pixel grid on the detector's physical origin, origin = -D ((size - 1)
   * / 2 * spacing), D the DetectorDirection (RTK's tools centre projections so): the reader's DetectorSize and
   * DetectorSpacing, or, writing, each geometry's own. Off: SetDetectorOrigin()'s. */
  itkSetMacro(DetectorOriginCentered, bool);
  itkGetConstMacro(DetectorOriginCentered, bool);
  itkBooleanMacro(DetectorOriginCentered);
  ///@}

  ///@{
  /** The direction of RTK's projection images (orthogonal, entries of any sign). Default identity: pixel (i, j) at
   * origin + (i du, j dv) along RTK's (x, y), which is DRRProjectionGeometry's ColumnsMirrored view (RTK's detector
   * axes x, y and the normal towards the source are right-handed). */
  itkSetMacro(DetectorDirection, DetectorDirectionType);
  itkGetConstReferenceMacro(DetectorDirection, DetectorDirectionType);
  ///@}

  /** Reads the file named by SetFileName(): one geometry per `Projection`, in file order. Throws an ExceptionObject
   * (see the class description) if it is a directory, cannot be opened or is not a valid RTK geometry. */
  GeometryListType
  Read() const;

  /** Writes geometries to the file named by SetFileName(), replacing it: written to a temporary file beside it, then
   * renamed over it, so that the file is never half-written. Throws an ExceptionObject, writing nothing, for an empty
   * list, a null or invalid geometry, one RTK cannot express (see the class description), or a file that cannot be
   * written. */
  void
  Write(const ConstGeometryListType & geometries) const;

  /** Reads the format from a stream (see Read()); errors name sourceName. */
  GeometryListType
  ReadFromStream(std::istream & stream, const std::string & sourceName = "") const;

  /** Writes the format to a stream (see Write()); nothing is written if a geometry is refused. */
  void
  WriteToStream(std::ostream & stream, const ConstGeometryListType & geometries) const;

  /** RTK's matrix of a view (rtk::ThreeDCircularProjectionGeometry::AddProjectionInRadians()): P = T(sx - px, sy - py)
   * M(-sdd, -sid) T(-sx, -sy, 0) Rz(-ia) Rx(-oa) Ry(-ga); a room point X goes to the detector physical point
   * (p0 / p2, p1 / p2), p = P [X; 1]. */
  static RTKMatrixType
  ComputeRTKMatrix(const ProjectionParameters & parameters);

  /** The geometry of a view from RTK's parameters, with the detector pixel grid in force (DetectorSize,
   * DetectorSpacing, origin, DetectorDirection). Throws an ExceptionObject for parameters it cannot express. */
  DRRProjectionGeometry::Pointer
  MakeGeometry(const ProjectionParameters & parameters) const;

  /** RTK's parameters of a geometry, its pixel grid placed by the origin and DetectorDirection in force (the
   * inverse of MakeGeometry()). Angles come out in [0, 360) degrees, as RTK stores them. Throws an ExceptionObject
   * for a null, invalid or localizer geometry, or one RTK's axes cannot express. */
  ProjectionParameters
  ComputeParameters(const DRRProjectionGeometry * geometry) const;

protected:
  DRRRTKGeometryFileIO();
  ~DRRRTKGeometryFileIO() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  /** The origin of a pixel grid of this size and spacing under the settings in force. */
  DetectorVectorType
  ComputeDetectorOrigin(const DetectorSizeType & size, const DetectorVectorType & spacing) const;
  /** Throws unless the DetectorDirection is finite and orthogonal. */
  void
  VerifyDetectorDirection() const;

  std::string           m_FileName;
  DetectorSizeType      m_DetectorSize;
  DetectorVectorType    m_DetectorSpacing;
  DetectorVectorType    m_DetectorOrigin;
  bool                  m_DetectorOriginCentered{ true };
  DetectorDirectionType m_DetectorDirection;
};
} // namespace itk

#endif
