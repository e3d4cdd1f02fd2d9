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
#ifndef itkDRRProjectionMatrixFileIO_h
#define itkDRRProjectionMatrixFileIO_h

#include "itkDRRCompatibility.h"
#include "itkDRRProjectionGeometry.h"
#include "PointBasedDRRExport.h"

#include <istream>
#include <ostream>
#include <string>

namespace itk
{
/** \class DRRProjectionMatrixFileIO
 * \brief Reads and writes a 3 x 4 projection matrix as text: the format of numpy.savetxt and of most C-arm
 * calibrations.
 *
 * Twelve finite numbers, row after row (three rows of four), separated by white space or commas; `#` starts a comment,
 * blank lines are skipped. The matrix maps a homogeneous room point (mm) to a homogeneous pixel (column, row, 1), pixel
 * indices as a DRR output's (centre of pixel 0 at 0): DRRProjectionGeometry::SetProjectionMatrix() takes it (with the
 * detector size, which a matrix does not say), and GetProjectionMatrix() gives it. Reading refuses, with an
 * ExceptionObject naming the file and line, a value that is not a finite number and any count other than 12 (a row
 * with other than four values names its line).
 *
 * \sa DRRProjectionGeometry, DRRProjectionGeometryFileIO
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRProjectionMatrixFileIO : public Object
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRProjectionMatrixFileIO);

  /** Standard class type aliases. */
  using Self = DRRProjectionMatrixFileIO;
  using Superclass = Object;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(DRRProjectionMatrixFileIO);

  /** The matrix read or written. */
  using MatrixType = DRRProjectionGeometry::ProjectionMatrixType;

  ///@{
  /** The file Read() reads and Write() writes. */
  itkSetStringMacro(FileName);
  itkGetStringMacro(FileName);
  ///@}

  /** Reads the file named by SetFileName(). Throws an ExceptionObject if it is a directory, cannot be opened or is not
   * a matrix. */
  MatrixType
  Read() const;

  /** Writes matrix to the file named by SetFileName(), replacing it: three lines of four numbers that read back bit for
   * bit. Throws an ExceptionObject for a non-finite entry (before writing) or a file that cannot be written. */
  void
  Write(const MatrixType & matrix) const;

  /** Reads the format from a stream; errors name `sourceName:line: `. */
  static MatrixType
  ReadFromStream(std::istream & stream, const std::string & sourceName = "");

  /** Writes the format to a stream (see Write()). */
  static void
  WriteToStream(std::ostream & stream, const MatrixType & matrix);

protected:
  DRRProjectionMatrixFileIO() = default;
  ~DRRProjectionMatrixFileIO() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  std::string m_FileName;
};
} // namespace itk

#endif
