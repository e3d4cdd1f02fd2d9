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
#ifndef itkDRRProjectionGeometryFileIO_h
#define itkDRRProjectionGeometryFileIO_h

#include "itkDRRCompatibility.h"
#include "itkDRRProjectionGeometry.h"

#include <istream>
#include <ostream>
#include <string>

namespace itk
{
/** \class DRRProjectionGeometryFileIO
 * \brief Reads and writes a DRRProjectionGeometry in the module's geometry-file format.
 *
 * The format is text, one `key value...` per line; `#` starts a comment, blank lines are skipped, keys are lower case
 * and values are separated by white space. Lengths are in mm, angles in degrees:
 *
 * | key | values | sets |
 * |---|---|---|
 * | `projection` | `perspective`, `parallel` or `localizer` (the registered beams) | SetProjection() |
 * | `sad` | SAD, mm | SetSourceToIsocenterDistance() |
 * | `sid` | SID, mm | SetSourceToDetectorDistance() |
 * | `gantry` | angle, degrees | SetGantryAngleInDegrees() |
 * | `nrm` | x y z (normalized) | SetNormal() |
 * | `vup` | x y z | SetViewUp() |
 * | `isocenter` | x y z, mm | SetIsocenter() |
 * | `cols`, `rows` | whole number in [1, 1e6] | SetDetectorSize() |
 * | `spacing` | du dv, mm | SetDetectorSpacing() |
 * | `offset` | offset_u offset_v, mm | SetDetectorOffset() |
 * | `mirror` | 0 or 1 | SetColumnsMirrored() |
 *
 * Reading applies the keys in file order to the geometry given, so keys not in the file keep the geometry's values;
 * an unknown key, a wrong number of values or a value that is not a finite number (in the strict form of the module's
 * text inputs) throws an ExceptionObject naming the line (`file:line: `), after the lines before it have been applied.
 *
 * Writing writes every key, numbers in the shortest decimal form that reads back to the same double (hexadecimal,
 * `%a`, for a subnormal number, whose decimal form the reader refuses), so that reading the file into any geometry
 * gives the written one bit for bit: the gantry angle is written, then `nrm` if the normal in force is not the gantry
 * angle's (SetNormal() keeps a vector that is already a unit vector). One exception: the explicit forms given column
 * and row directions orthogonal only to within their tolerance (1e-6) hold a normal n = v x u that is not of unit
 * length to 4 eps, and it reads back normalized. A geometry the reader would refuse (a non-finite value, a detector
 * size outside [1, 1e6]) is not written: Write() throws.
 *
 * Other formats (projection matrices, RTK's XML) are meant to be sibling IO classes, as ITK has an ImageIO or a
 * TransformIO per file format. DRRProjectionGeometry::ReadGeometryFile() and ReadGeometry() call this class.
 *
 * \sa DRRProjectionGeometry
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRProjectionGeometryFileIO : public Object
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRProjectionGeometryFileIO);

  /** Standard class type aliases. */
  using Self = DRRProjectionGeometryFileIO;
  using Superclass = Object;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(DRRProjectionGeometryFileIO);

  /** The geometry read or written. */
  using GeometryType = DRRProjectionGeometry;

  ///@{
  /** The geometry file Read() reads and Write() writes. */
  itkSetStringMacro(FileName);
  itkGetStringMacro(FileName);
  ///@}

  /** Reads the file named by SetFileName() into geometry (see the class documentation). Throws an ExceptionObject if
   * the file is a directory or cannot be opened, or naming the line of the first error. */
  void
  Read(GeometryType * geometry);

  /** Writes geometry to the file named by SetFileName(), replacing it. Throws an ExceptionObject if the geometry
   * cannot be read back (a non-finite value, a detector size outside [1, 1e6]) or the file cannot be written. */
  void
  Write(const GeometryType * geometry);

  /** Reads the format from a stream into geometry, as Read() does for a file (which calls this): each line is given
   * to ParseLine(), errors name `sourceName:line: ` (or `line N: ` without a source name). Lines before an
   * erroneous one are applied. */
  static void
  ReadFromStream(std::istream & stream, GeometryType * geometry, const std::string & sourceName = "");

  /** Writes geometry to a stream in the format, every key (see Write()). Throws as Write() does, before writing
   * anything. */
  static void
  WriteToStream(std::ostream & stream, const GeometryType * geometry);

  /** Parses one line of the format (without the trailing newline) into geometry; where (e.g. `file.txt:3: `)
   * prefixes the error messages. Throws on error. */
  static void
  ParseLine(const std::string & line, GeometryType * geometry, const std::string & where = "");

protected:
  DRRProjectionGeometryFileIO() = default;
  ~DRRProjectionGeometryFileIO() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  std::string m_FileName;
};
} // namespace itk

#endif
