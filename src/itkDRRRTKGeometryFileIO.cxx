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
#include "itkDRRRTKGeometryFileIO.h"
#include "itkDRRDOMNodeXMLReader.h"
#include "itkDRRNumberParser.h"
#include "itkEuler3DTransform.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <limits>
#include <sstream>

// The XML is parsed by ITK's DOMNodeXMLReader (ITKIOXML, expat), as RTK's own reader parses it with expat, through
// DRRDOMNodeXMLReader (src/itkDRRDOMNodeXMLReader.h), which adds what ITK's reader leaves out.

namespace itk
{
namespace
{
[[noreturn]] void
ThrowRTKError(const std::string & message)
{
  ExceptionObject e(__FILE__, __LINE__, "DRRRTKGeometryFileIO: " + message, ITK_LOCATION);
  throw e;
}

std::string
Lower(std::string text)
{
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

using Matrix3x3 = Matrix<double, 3, 3>;

// RTK's rotation: rtk::ThreeDCircularProjectionGeometry::ComputeRotationHomogeneousMatrix(-oa, -ga, -ia), an
// itk::CenteredEuler3DTransform's SetRotation(angleX, angleY, angleZ) in ZXY order: Rz(-ia) Rx(-oa) Ry(-ga). Its rows
// are RTK's detector x axis, y axis and the normal towards the source, in room coordinates.
Matrix3x3
RTKRotation(double gantryDegrees, double outOfPlaneDegrees, double inPlaneDegrees)
{
  const double degreesToRadians = std::atan(1.0) / 45.0; // as RTK's AddProjection()
  using EulerType = Euler3DTransform<double>;
  auto euler = EulerType::New();
  euler->SetComputeZYX(false);
  euler->SetRotation(
    -degreesToRadians * outOfPlaneDegrees, -degreesToRadians * gantryDegrees, -degreesToRadians * inPlaneDegrees);
  return euler->GetMatrix();
}

DRRProjectionGeometry::VectorType
Row(const Matrix3x3 & m, unsigned int r)
{
  DRRProjectionGeometry::VectorType v;
  for (unsigned int c = 0; c < 3; ++c)
  {
    v[c] = m[r][c];
  }
  return v;
}

double
WrapDegrees(double a)
{
  const double wrapped = a - 360.0 * std::floor(a / 360.0); // RTK's ConvertAngleBetween0And360Degrees
  return wrapped >= 360.0 ? 0.0 : wrapped + 0.0;
}

// The reader's state: RTK's reader keeps every value from one element to the next, across projections.
struct ReaderValue
{
  double Value{ 0.0 };
  bool   Given{ false };
};

// An ExceptionObject's description without this class's prefix, to be wrapped in a message with more context.
std::string
DescriptionOf(const ExceptionObject & e)
{
  std::string       description = e.GetDescription();
  const std::string prefix = "DRRRTKGeometryFileIO: ";
  if (description.compare(0, prefix.size(), prefix) == 0)
  {
    description = description.substr(prefix.size());
  }
  return description;
}

std::string
NumberText(double value)
{
  std::ostringstream text;
  text << std::setprecision(17) << value + 0.0; // + 0.0: no negative zero
  return text.str();
}
} // namespace

DRRRTKGeometryFileIO::DRRRTKGeometryFileIO()
{
  m_DetectorSize.Fill(256);
  m_DetectorSpacing.Fill(1.0);
  m_DetectorOrigin.Fill(0.0);
  m_DetectorDirection.SetIdentity();
}

void
DRRRTKGeometryFileIO::SetDetectorOrigin(const DetectorVectorType & origin)
{
  if (m_DetectorOrigin != origin || m_DetectorOriginCentered)
  {
    m_DetectorOrigin = origin;
    m_DetectorOriginCentered = false;
    this->Modified();
  }
}

void
DRRRTKGeometryFileIO::VerifyDetectorDirection() const
{
  const auto & d = m_DetectorDirection;
  bool         ok = true;
  for (unsigned int r = 0; r < 2; ++r)
  {
    for (unsigned int c = 0; c < 2; ++c)
    {
      ok = ok && std::isfinite(d[r][c]);
    }
  }
  ok = ok && std::abs(d[0][0] * d[0][0] + d[1][0] * d[1][0] - 1.0) <= 1e-6 &&
       std::abs(d[0][1] * d[0][1] + d[1][1] * d[1][1] - 1.0) <= 1e-6 &&
       std::abs(d[0][0] * d[0][1] + d[1][0] * d[1][1]) <= 1e-6;
  if (!ok)
  {
    ThrowRTKError("the DetectorDirection must be a finite orthogonal 2 x 2 matrix");
  }
}

DRRRTKGeometryFileIO::DetectorVectorType
DRRRTKGeometryFileIO::ComputeDetectorOrigin(const DetectorSizeType & size, const DetectorVectorType & spacing) const
{
  if (!m_DetectorOriginCentered)
  {
    if (!std::isfinite(m_DetectorOrigin[0]) || !std::isfinite(m_DetectorOrigin[1]))
    {
      ThrowRTKError("the DetectorOrigin must be finite");
    }
    return m_DetectorOrigin;
  }
  // -D ((size - 1) / 2 spacing): the grid's centre at the detector's physical origin.
  const double       halfColumns = 0.5 * (static_cast<double>(size[0]) - 1.0) * spacing[0];
  const double       halfRows = 0.5 * (static_cast<double>(size[1]) - 1.0) * spacing[1];
  DetectorVectorType origin;
  for (unsigned int r = 0; r < 2; ++r)
  {
    origin[r] = -(m_DetectorDirection[r][0] * halfColumns + m_DetectorDirection[r][1] * halfRows) + 0.0;
  }
  return origin;
}

DRRRTKGeometryFileIO::RTKMatrixType
DRRRTKGeometryFileIO::ComputeRTKMatrix(const ProjectionParameters & p)
{
  // rtk::ThreeDCircularProjectionGeometry::AddProjectionInRadians(): the product of the projection translation, the
  // magnification (ComputeProjectionMagnificationMatrix(-sdd, -sid)), the source translation and the rotation, in
  // this order and association.
  const double sdd = p.SourceToDetectorDistance;
  const double sid = p.SourceToIsocenterDistance;

  vnl_matrix<double> projectionTranslation(3, 3, 0.0);
  projectionTranslation.set_identity();
  projectionTranslation(0, 2) = p.SourceOffsetX - p.ProjectionOffsetX;
  projectionTranslation(1, 2) = p.SourceOffsetY - p.ProjectionOffsetY;

  vnl_matrix<double> magnification(3, 4, 0.0);
  magnification(0, 0) = (sdd == 0.0) ? 1.0 : -sdd;
  magnification(1, 1) = (sdd == 0.0) ? 1.0 : -sdd;
  magnification(2, 2) = (sdd == 0.0) ? 0.0 : 1.0;
  magnification(2, 3) = (sdd == 0.0) ? 1.0 : -sid;

  vnl_matrix<double> sourceTranslation(4, 4, 0.0);
  sourceTranslation.set_identity();
  sourceTranslation(0, 3) = -p.SourceOffsetX;
  sourceTranslation(1, 3) = -p.SourceOffsetY;

  const Matrix3x3    r = RTKRotation(p.GantryAngle, p.OutOfPlaneAngle, p.InPlaneAngle);
  vnl_matrix<double> rotation(4, 4, 0.0);
  rotation.set_identity();
  for (unsigned int i = 0; i < 3; ++i)
  {
    for (unsigned int j = 0; j < 3; ++j)
    {
      rotation(i, j) = r[i][j];
    }
  }
  const vnl_matrix<double> product = projectionTranslation * magnification * sourceTranslation * rotation;
  RTKMatrixType            matrix;
  for (unsigned int i = 0; i < 3; ++i)
  {
    for (unsigned int j = 0; j < 4; ++j)
    {
      matrix[i][j] = product(i, j);
    }
  }
  return matrix;
}

DRRProjectionGeometry::Pointer
DRRRTKGeometryFileIO::MakeGeometry(const ProjectionParameters & p) const
{
  const double values[] = {
    p.GantryAngle,   p.OutOfPlaneAngle,          p.InPlaneAngle,      p.SourceToIsocenterDistance, p.SourceOffsetX,
    p.SourceOffsetY, p.SourceToDetectorDistance, p.ProjectionOffsetX, p.ProjectionOffsetY
  };
  if (!std::all_of(std::begin(values), std::end(values), [](double v) { return std::isfinite(v); }))
  {
    ThrowRTKError("the parameters must be finite");
  }
  if (p.SourceToDetectorDistance < 0.0)
  {
    ThrowRTKError("SourceToDetectorDistance " + NumberText(p.SourceToDetectorDistance) +
                  " is negative (a detector behind the source; 0 is a parallel beam)");
  }
  if (!(p.SourceToIsocenterDistance > 0.0))
  {
    ThrowRTKError("SourceToIsocenterDistance " + NumberText(p.SourceToIsocenterDistance) +
                  " is not positive (the source must be on the detector's side of the isocenter, along the normal" +
                  (p.SourceToDetectorDistance == 0.0 ? std::string("; a parallel beam's detector lies that far behind "
                                                                   "the isocenter)")
                                                     : std::string(")")));
  }
  this->VerifyDetectorDirection();
  const DetectorVectorType origin = this->ComputeDetectorOrigin(m_DetectorSize, m_DetectorSpacing);

  using VectorType = DRRProjectionGeometry::VectorType;
  using PointType = DRRProjectionGeometry::PointType;
  const Matrix3x3  rotation = RTKRotation(p.GantryAngle, p.OutOfPlaneAngle, p.InPlaneAngle);
  const VectorType ex = Row(rotation, 0);
  const VectorType ey = Row(rotation, 1);
  const VectorType ez = Row(rotation, 2);
  const auto &     d = m_DetectorDirection;
  const VectorType column = ex * d[0][0] + ey * d[1][0];
  const VectorType row = ex * d[0][1] + ey * d[1][1];

  const bool parallel = p.SourceToDetectorDistance == 0.0;
  // Perspective: the source S = sx x + sy y + sid z; our isocenter the foot of S on the plane through RTK's isocenter
  // parallel to the detector, SAD = sid, SID = sdd. Parallel: S = sid z, the detector plane sid behind the isocenter
  // (RTK's GetProjectionCoordinatesToDetectorSystemMatrix()): SAD = sid, SID = 2 sid.
  const double sx = parallel ? 0.0 : p.SourceOffsetX;
  const double sy = parallel ? 0.0 : p.SourceOffsetY;
  PointType    isocenter;
  isocenter.Fill(0.0);
  isocenter += ex * sx + ey * sy;

  auto geometry = DRRProjectionGeometry::New();
  geometry->SetProjection(parallel ? PointBasedDRREnums::Projection::Parallel
                                   : PointBasedDRREnums::Projection::Perspective);
  geometry->SetNormal(ez);
  geometry->SetViewUp(-row);
  geometry->SetColumnsMirrored(column * CrossProduct(ez, row) < 0.0);
  geometry->SetIsocenter(isocenter);
  geometry->SetSourceToIsocenterDistance(p.SourceToIsocenterDistance);
  geometry->SetSourceToDetectorDistance(parallel ? 2.0 * p.SourceToIsocenterDistance : p.SourceToDetectorDistance);
  geometry->SetDetectorSize(m_DetectorSize);
  geometry->SetDetectorSpacing(m_DetectorSpacing);
  // Pixel (0, 0) is at (px + o_x) x + (py + o_y) y in the detector plane; ours at the foot of the normal plus
  // (offset - (size - 1) / 2 spacing) along the column and row directions.
  const double       wx = p.ProjectionOffsetX + origin[0] - sx;
  const double       wy = p.ProjectionOffsetY + origin[1] - sy;
  DetectorVectorType offset;
  offset[0] = 0.5 * (static_cast<double>(m_DetectorSize[0]) - 1.0) * m_DetectorSpacing[0] + wx * d[0][0] + wy * d[1][0];
  offset[1] = 0.5 * (static_cast<double>(m_DetectorSize[1]) - 1.0) * m_DetectorSpacing[1] + wx * d[0][1] + wy * d[1][1];
  geometry->SetDetectorOffset(offset);
  geometry->VerifyGeometry();
  return geometry;
}

DRRRTKGeometryFileIO::ProjectionParameters
DRRRTKGeometryFileIO::ComputeParameters(const DRRProjectionGeometry * geometry) const
{
  if (geometry == nullptr)
  {
    ThrowRTKError("a geometry is null");
  }
  geometry->VerifyGeometry();
  const auto projection = geometry->GetProjection();
  if (projection != PointBasedDRREnums::Projection::Perspective &&
      projection != PointBasedDRREnums::Projection::Parallel)
  {
    ThrowRTKError("RTK's geometry has perspective and parallel beams only, not a localizer's (a fan across the "
                  "columns, parallel along the rows)");
  }
  this->VerifyDetectorDirection();
  using VectorType = DRRProjectionGeometry::VectorType;
  const auto &     d = m_DetectorDirection;
  const VectorType column = geometry->GetColumnDirection();
  const VectorType row = geometry->GetRowDirection();
  const VectorType n = geometry->GetNormal();
  // [column row] = [x y] D, D orthogonal: [x y] = [column row] D^T.
  const VectorType ex = column * d[0][0] + row * d[0][1];
  const VectorType ey = column * d[1][0] + row * d[1][1];
  if (!(CrossProduct(ex, ey) * n > 0.0))
  {
    ThrowRTKError(std::string("with this DetectorDirection, RTK's detector axes x, y and the normal towards the source "
                              "would be left-handed: the view's columns are ") +
                  (geometry->GetColumnsMirrored() ? "mirrored" : "not mirrored") +
                  "; flip ColumnsMirrored or one axis of the DetectorDirection (RTK's projection seen from the "
                  "source has its rows reversed)");
  }
  // R = Rz(a) Rx(b) Ry(g), rows x, y, n: row 2 = (-cos b sin g, sin b, cos b cos g), R01 = -sin a cos b,
  // R11 = cos a cos b. RTK's angles are the opposites (ComputeRotationHomogeneousMatrix(-oa, -ga, -ia)).
  const double cosB = std::hypot(n[0], n[2]);
  const double b = std::atan2(n[1], cosB);
  double       a = 0.0;
  double       g = 0.0;
  if (cosB > 1e-12)
  {
    g = std::atan2(-n[0], n[2]);
    a = std::atan2(-ex[1], ey[1]);
  }
  else
  {
    // Gimbal lock (out-of-plane angle +-90 degrees): the in-plane angle 0, as RTK's FixAngles() chooses; row 0 is then
    // (cos g, 0, sin g).
    g = std::atan2(ex[2], ex[0]);
  }
  const double         radiansToDegrees = 45.0 / std::atan(1.0);
  ProjectionParameters p;
  p.GantryAngle = WrapDegrees(-g * radiansToDegrees);
  p.OutOfPlaneAngle = WrapDegrees(-b * radiansToDegrees);
  p.InPlaneAngle = WrapDegrees(-a * radiansToDegrees);

  // The rest in RTK's own axes, recomputed from the angles written, so that the file is consistent.
  const Matrix3x3  rotation = RTKRotation(p.GantryAngle, p.OutOfPlaneAngle, p.InPlaneAngle);
  const VectorType rx = Row(rotation, 0);
  const VectorType ry = Row(rotation, 1);
  const VectorType rz = Row(rotation, 2);
  if ((rx - ex).GetNorm() > 1e-9 || (ry - ey).GetNorm() > 1e-9 || (rz - n).GetNorm() > 1e-9)
  {
    ThrowRTKError("the detector orientation could not be decomposed into RTK's angles");
  }
  const auto pixel = geometry->GetPixelCenter(0.0, 0.0).GetVectorFromOrigin();
  const auto origin = this->ComputeDetectorOrigin(geometry->GetDetectorSize(), geometry->GetDetectorSpacing());
  if (projection == PointBasedDRREnums::Projection::Perspective)
  {
    const auto source = geometry->GetSourcePosition().GetVectorFromOrigin();
    p.SourceOffsetX = source * rx + 0.0;
    p.SourceOffsetY = source * ry + 0.0;
    p.SourceToIsocenterDistance = source * rz;
    p.SourceToDetectorDistance = geometry->GetSourceToDetectorDistance();
  }
  else
  {
    p.SourceToIsocenterDistance = -(geometry->GetDetectorPlaneOrigin().GetVectorFromOrigin() * rz);
    p.SourceToDetectorDistance = 0.0;
  }
  if (!(p.SourceToIsocenterDistance > 0.0))
  {
    ThrowRTKError(std::string("RTK's isocenter is the room origin, and it must lie ") +
                  (projection == PointBasedDRREnums::Projection::Perspective
                     ? "in front of the source, towards the detector,"
                     : "in front of the detector plane") +
                  " along the normal: SourceToIsocenterDistance would be " + NumberText(p.SourceToIsocenterDistance) +
                  " mm (move the volume's origin)");
  }
  p.ProjectionOffsetX = pixel * rx - origin[0] + 0.0;
  p.ProjectionOffsetY = pixel * ry - origin[1] + 0.0;
  return p;
}

DRRRTKGeometryFileIO::GeometryListType
DRRRTKGeometryFileIO::Read() const
{
  std::error_code error;
  if (std::filesystem::is_directory(m_FileName, error))
  {
    ThrowRTKError("cannot read RTK geometry file '" + m_FileName + "': it is a directory");
  }
  std::ifstream file(m_FileName, std::ios::in | std::ios::binary);
  if (!file)
  {
    ThrowRTKError("cannot open RTK geometry file '" + m_FileName + "'");
  }
  return this->ReadFromStream(file, m_FileName);
}

DRRRTKGeometryFileIO::GeometryListType
DRRRTKGeometryFileIO::ReadFromStream(std::istream & stream, const std::string & sourceName) const
{
  const std::string where = sourceName.empty() ? std::string() : sourceName + ": ";
  const std::string text{ std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>() };
  if (stream.bad())
  {
    ThrowRTKError(where + "read error");
  }
  const auto reader = DRRDOMNodeXMLReader::New();
  reader->Parse(text, "DRRRTKGeometryFileIO: " + where);
  const DOMNode & root = *reader->GetOutput();
  if (root.GetName() != "RTKThreeDCircularGeometry")
  {
    ThrowRTKError(where + "the root element is <" + root.GetName() + ">, not RTK's <RTKThreeDCircularGeometry>");
  }
  if (!root.HasAttribute("version"))
  {
    ThrowRTKError(where + "<RTKThreeDCircularGeometry> has no version attribute");
  }
  const std::string version = root.GetAttribute("version");
  // RTK's reader (CurrentVersion 3) reads versions 3 and 2.
  if (version != "3" && version != "2")
  {
    ThrowRTKError(where + "version \"" + version + "\" of RTKThreeDCircularGeometry is not supported (2 and 3 are)");
  }

  // RTK's parameters: all of them carry over from element to element (RTK's reader never resets them).
  enum Key
  {
    Gantry,
    OutOfPlane,
    InPlane,
    SID,
    SourceX,
    SourceY,
    SDD,
    ProjectionX,
    ProjectionY,
    Radius,
    CollimationUInf,
    CollimationUSup,
    CollimationVInf,
    CollimationVSup,
    KeyCount
  };
  const char * const names[KeyCount] = { "GantryAngle",
                                         "OutOfPlaneAngle",
                                         "InPlaneAngle",
                                         "SourceToIsocenterDistance",
                                         "SourceOffsetX",
                                         "SourceOffsetY",
                                         "SourceToDetectorDistance",
                                         "ProjectionOffsetX",
                                         "ProjectionOffsetY",
                                         "RadiusCylindricalDetector",
                                         "CollimationUInf",
                                         "CollimationUSup",
                                         "CollimationVInf",
                                         "CollimationVSup" };
  ReaderValue        state[KeyCount];

  // Parses a parameter element into the state; false if the element is not one (ignored, as RTK's reader does).
  const auto readParameter = [&](const DOMNode & element, const std::string & context) -> bool {
    std::string name = Lower(element.GetName());
    if (name == "angle") // RTK's older name of GantryAngle
    {
      name = "gantryangle";
    }
    for (unsigned int k = 0; k < KeyCount; ++k)
    {
      if (name == Lower(names[k]))
      {
        std::string value = DRRDOMNodeXMLReader::GetText(element);
        const auto  notSpace = [](unsigned char c) { return !std::isspace(c); };
        value.erase(value.begin(), std::find_if(value.begin(), value.end(), notSpace));
        value.erase(std::find_if(value.rbegin(), value.rend(), notSpace).base(), value.end());
        double number = 0.0;
        if (!DRRNumberParser::ParseFiniteNumber(value, number))
        {
          ThrowRTKError(where + context + "<" + element.GetName() + "> '" + value + "' is not a finite number");
        }
        state[k].Value = number;
        state[k].Given = true;
        return true;
      }
    }
    return false;
  };

  GeometryListType geometries;
  bool             parallelSeen = false;
  for (const DOMNode * child : DRRDOMNodeXMLReader::GetElements(root))
  {
    if (Lower(child->GetName()) != "projection")
    {
      readParameter(*child, std::string());
      continue;
    }
    const size_t      index = geometries.size();
    const std::string context = "projection " + std::to_string(index) + " (counted from 0): ";
    bool              gantryHere = false;
    bool              matrixHere = false;
    RTKMatrixType     stored;
    for (const DOMNode * element : DRRDOMNodeXMLReader::GetElements(*child))
    {
      if (Lower(element->GetName()) == "matrix")
      {
        std::istringstream  tokens(DRRDOMNodeXMLReader::GetText(*element));
        std::vector<double> entries;
        for (std::string token; tokens >> token;)
        {
          double number = 0.0;
          if (!DRRNumberParser::ParseFiniteNumber(token, number))
          {
            ThrowRTKError(where + context + "<Matrix> entry '" + token + "' is not a finite number");
          }
          entries.push_back(number);
        }
        if (entries.size() != 12)
        {
          ThrowRTKError(where + context + "<Matrix> has " + std::to_string(entries.size()) +
                        " numbers, a 3 x 4 matrix has 12");
        }
        for (unsigned int i = 0; i < 12; ++i)
        {
          stored[i / 4][i % 4] = entries[i];
        }
        matrixHere = true;
      }
      else if (readParameter(*element, context))
      {
        const std::string name = Lower(element->GetName());
        gantryHere = gantryHere || name == "gantryangle" || name == "angle";
      }
    }
    if (!gantryHere)
    {
      ThrowRTKError(where + context + "no <GantryAngle>");
    }
    if (!matrixHere)
    {
      ThrowRTKError(where + context + "no <Matrix>");
    }
    if (state[Radius].Given && state[Radius].Value != 0.0)
    {
      ThrowRTKError(where + context + "<RadiusCylindricalDetector> " + NumberText(state[Radius].Value) +
                    ": a cylindrical detector is not supported (DRRProjectionGeometry's detector is flat)");
    }
    for (unsigned int k = CollimationUInf; k <= CollimationVSup; ++k)
    {
      if (state[k].Given && state[k].Value != std::numeric_limits<double>::max())
      {
        ThrowRTKError(where + context + "<" + names[k] + ">: a collimated view is not supported");
      }
    }
    if (!state[SID].Given)
    {
      ThrowRTKError(where + context + "no <SourceToIsocenterDistance>, neither global nor in the projection");
    }
    ProjectionParameters p;
    p.GantryAngle = state[Gantry].Value;
    p.OutOfPlaneAngle = state[OutOfPlane].Value;
    p.InPlaneAngle = state[InPlane].Value;
    p.SourceToIsocenterDistance = state[SID].Value;
    p.SourceOffsetX = state[SourceX].Value;
    p.SourceOffsetY = state[SourceY].Value;
    p.SourceToDetectorDistance = state[SDD].Value; // RTK's default 0: a parallel beam
    p.ProjectionOffsetX = state[ProjectionX].Value;
    p.ProjectionOffsetY = state[ProjectionY].Value;
    const bool parallel = p.SourceToDetectorDistance == 0.0;
    if (index > 0 && parallel != parallelSeen)
    {
      // RTK's AddProjectionInRadians() refuses the mixture.
      ThrowRTKError(where + context + (parallel ? "a parallel" : "a divergent") + " projection after " +
                    (parallel ? "divergent" : "parallel") + " ones: RTK does not mix them");
    }
    parallelSeen = parallel;
    DRRProjectionGeometry::Pointer geometry;
    try
    {
      geometry = this->MakeGeometry(p);
    }
    catch (const ExceptionObject & e)
    {
      ThrowRTKError(where + context + DescriptionOf(e));
    }
    const RTKMatrixType computed = ComputeRTKMatrix(p);
    for (unsigned int i = 0; i < 3; ++i)
    {
      for (unsigned int j = 0; j < 4; ++j)
      {
        // RTK's reader's tolerance (ThreeDCircularProjectionGeometryXMLFileReader::EndElement()).
        if (std::abs(stored[i][j] - computed[i][j]) > 0.001)
        {
          ThrowRTKError(where + context + "<Matrix> entry (" + std::to_string(i) + ", " + std::to_string(j) + ") " +
                        NumberText(stored[i][j]) + " is not the " + NumberText(computed[i][j]) +
                        " computed from the parameters (RTK's tolerance 0.001)");
        }
      }
    }
    geometries.push_back(geometry);
  }
  if (geometries.empty())
  {
    ThrowRTKError(where + "no <Projection>: the geometry has no view");
  }
  return geometries;
}

void
DRRRTKGeometryFileIO::WriteToStream(std::ostream & stream, const ConstGeometryListType & geometries) const
{
  if (geometries.empty())
  {
    ThrowRTKError("no geometry to write: RTK's writer refuses an empty geometry");
  }
  std::vector<ProjectionParameters> views;
  for (size_t i = 0; i < geometries.size(); ++i)
  {
    try
    {
      views.push_back(this->ComputeParameters(geometries[i].GetPointer()));
    }
    catch (const ExceptionObject & e)
    {
      ThrowRTKError("geometry " + std::to_string(i) + " (counted from 0): " + DescriptionOf(e));
    }
    if ((views.back().SourceToDetectorDistance == 0.0) != (views.front().SourceToDetectorDistance == 0.0))
    {
      ThrowRTKError("geometry " + std::to_string(i) +
                    " (counted from 0): RTK does not mix parallel and divergent views");
    }
  }
  using Member = double ProjectionParameters::*;
  struct Field
  {
    const char * Name;
    Member       Value;
  };
  // RTK's writer's order; GantryAngle always per projection.
  const Field        fields[] = { { "SourceToIsocenterDistance", &ProjectionParameters::SourceToIsocenterDistance },
                                  { "SourceToDetectorDistance", &ProjectionParameters::SourceToDetectorDistance },
                                  { "SourceOffsetX", &ProjectionParameters::SourceOffsetX },
                                  { "SourceOffsetY", &ProjectionParameters::SourceOffsetY },
                                  { "ProjectionOffsetX", &ProjectionParameters::ProjectionOffsetX },
                                  { "ProjectionOffsetY", &ProjectionParameters::ProjectionOffsetY },
                                  { "InPlaneAngle", &ProjectionParameters::InPlaneAngle },
                                  { "OutOfPlaneAngle", &ProjectionParameters::OutOfPlaneAngle } };
  std::vector<bool>  global;
  std::ostringstream text;
  text << "<?xml version=\"1.0\"?>\n<!DOCTYPE RTKGEOMETRY>\n<RTKThreeDCircularGeometry version=\"3\">\n";
  for (const auto & field : fields)
  {
    const double first = views.front().*field.Value;
    const bool   shared =
      std::all_of(views.begin(), views.end(), [&](const ProjectionParameters & v) { return v.*field.Value == first; });
    global.push_back(shared);
    if (shared && first != 0.0) // RTK's default, 0, is not written
    {
      text << "  <" << field.Name << ">" << NumberText(first) << "</" << field.Name << ">\n";
    }
  }
  for (const auto & view : views)
  {
    text << "  <Projection>\n    <GantryAngle>" << NumberText(view.GantryAngle) << "</GantryAngle>\n";
    for (size_t f = 0; f < std::size(fields); ++f)
    {
      if (!global[f])
      {
        text << "    <" << fields[f].Name << ">" << NumberText(view.*fields[f].Value) << "</" << fields[f].Name
             << ">\n";
      }
    }
    const RTKMatrixType matrix = ComputeRTKMatrix(view);
    text << "    <Matrix>\n";
    for (unsigned int i = 0; i < 3; ++i)
    {
      text << "     ";
      for (unsigned int j = 0; j < 4; ++j)
      {
        text << ' ' << NumberText(matrix[i][j]);
      }
      text << '\n';
    }
    text << "    </Matrix>\n  </Projection>\n";
  }
  text << "</RTKThreeDCircularGeometry>\n";
  stream << text.str();
}

void
DRRRTKGeometryFileIO::Write(const ConstGeometryListType & geometries) const
{
  std::ostringstream text;
  this->WriteToStream(text, geometries);
  std::error_code error;
  if (m_FileName.empty() || std::filesystem::is_directory(m_FileName, error))
  {
    ThrowRTKError("cannot write RTK geometry file '" + m_FileName +
                  "': " + (m_FileName.empty() ? "no file name" : "it is a directory"));
  }
  const std::string temporary = m_FileName + ".tmp";
  {
    std::ofstream file(temporary, std::ios::out | std::ios::trunc | std::ios::binary);
    file << text.str();
    file.close(); // a short write or a failed close (a full disk) leaves the stream failed
    if (!file)
    {
      std::filesystem::remove(temporary, error);
      ThrowRTKError("cannot write RTK geometry file '" + m_FileName + "' (its temporary '" + temporary + "')");
    }
  }
  std::filesystem::rename(temporary, m_FileName, error);
  if (error)
  {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    ThrowRTKError("cannot write RTK geometry file '" + m_FileName +
                  "': renaming its temporary failed: " + error.message());
  }
}

void
DRRRTKGeometryFileIO::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << m_FileName << std::endl;
  os << indent << "DetectorSize: " << m_DetectorSize << std::endl;
  os << indent << "DetectorSpacing (mm): " << m_DetectorSpacing << std::endl;
  os << indent << "DetectorOrigin (mm): " << m_DetectorOrigin << std::endl;
  os << indent << "DetectorOriginCentered: " << (m_DetectorOriginCentered ? "On" : "Off") << std::endl;
  os << indent << "DetectorDirection: " << m_DetectorDirection[0][0] << ' ' << m_DetectorDirection[0][1] << "; "
     << m_DetectorDirection[1][0] << ' ' << m_DetectorDirection[1][1] << std::endl;
}
} // namespace itk
