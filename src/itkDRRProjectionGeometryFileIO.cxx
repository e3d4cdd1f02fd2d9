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
#include "itkDRRProjectionGeometryFileIO.h"
#include "itkDRRPolicies.h"
#include "itkDRRNumberParser.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

namespace itk
{
namespace
{
using GeometryType = DRRProjectionGeometry;

/** Errors of the format read as DRRProjectionGeometry's own (the messages predate this class). */
[[noreturn]] void
ThrowGeometryError(const std::string & message)
{
  ExceptionObject e(__FILE__, __LINE__, "DRRProjectionGeometry: " + message, ITK_LOCATION);
  throw e;
}

[[noreturn]] void
ThrowWriteError(const std::string & message)
{
  ExceptionObject e(__FILE__, __LINE__, "DRRProjectionGeometryFileIO: " + message, ITK_LOCATION);
  throw e;
}

void
CheckGeometry(const GeometryType * geometry)
{
  if (geometry == nullptr)
  {
    ExceptionObject e(__FILE__, __LINE__, "DRRProjectionGeometryFileIO: no geometry given", ITK_LOCATION);
    throw e;
  }
}

/** Strict number parsing: the whole token must be a finite number. */
double
ParseNumber(const std::string & token, const std::string & key, const std::string & where)
{
  double value = 0.0;
  if (!DRRNumberParser::ParseFiniteNumber(token, value))
  {
    ThrowGeometryError(where + "value '" + token + "' of key '" + key + "' is not a finite number");
  }
  return value;
}

SizeValueType
ParseCount(const std::string & token, const std::string & key, const std::string & where)
{
  const double value = ParseNumber(token, key, where);
  if (!DRRNumberParser::IsWholeNumberInRange(value, 1.0, 1e6))
  {
    ThrowGeometryError(where + "value '" + token + "' of key '" + key + "' must be a whole number in [1, 1e6]");
  }
  return static_cast<SizeValueType>(value);
}

/** Sets value through set, bit for bit: ITK's set macros skip a value equal to the one held, and -0 == 0, so a -0
 * read over a 0 would be lost (the geometry fuzzer's finding: `offset 0 -0` read back as 0 0). A different value
 * first makes the second set take. */
template <typename TValue, typename TSet, typename TGet>
void
SetBitExact(const TValue & value, TSet set, TGet get)
{
  set(value);
  const auto & held = get();
  if (std::memcmp(&held, &value, sizeof(TValue)) != 0)
  {
    TValue other = value;
    reinterpret_cast<double *>(&other)[0] += 1.0;
    set(other);
    set(value);
  }
}

void
ApplyKey(GeometryType *                   geometry,
         const std::string &              key,
         const std::vector<std::string> & values,
         const std::string &              where)
{
  auto expect = [&](size_t count) {
    if (values.size() != count)
    {
      ThrowGeometryError(where + "key '" + key + "' takes " + std::to_string(count) + " value(s), got " +
                         std::to_string(values.size()));
    }
  };
  auto vector3 = [&]() {
    expect(3);
    GeometryType::VectorType v;
    for (unsigned int d = 0; d < 3; ++d)
    {
      v[d] = ParseNumber(values[d], key, where);
    }
    return v;
  };
  auto vector2 = [&]() {
    expect(2);
    GeometryType::DetectorVectorType v;
    for (unsigned int d = 0; d < 2; ++d)
    {
      v[d] = ParseNumber(values[d], key, where);
    }
    return v;
  };

  if (key == "projection")
  {
    expect(1);
    GeometryType::ProjectionEnum beam;
    if (!DRRPolicies::Beams::FindByName(values[0], beam))
    {
      // The registered beams, "'a', 'b' or 'c'".
      const std::vector<std::string> names = DRRPolicies::Beams::GetNames();
      std::string                    list;
      for (size_t b = 0; b < names.size(); ++b)
      {
        list += (b == 0 ? "'" : b + 1 < names.size() ? ", '" : " or '") + names[b] + "'";
      }
      ThrowGeometryError(where + "projection must be " + list + ", got '" + values[0] + "'");
    }
    geometry->SetProjection(beam);
  }
  else if (key == "sad")
  {
    expect(1);
    SetBitExact(
      ParseNumber(values[0], key, where),
      [&](double v) { geometry->SetSourceToIsocenterDistance(v); },
      [&]() { return geometry->GetSourceToIsocenterDistance(); });
  }
  else if (key == "sid")
  {
    expect(1);
    SetBitExact(
      ParseNumber(values[0], key, where),
      [&](double v) { geometry->SetSourceToDetectorDistance(v); },
      [&]() { return geometry->GetSourceToDetectorDistance(); });
  }
  else if (key == "gantry")
  {
    expect(1);
    geometry->SetGantryAngleInDegrees(ParseNumber(values[0], key, where));
  }
  else if (key == "nrm")
  {
    geometry->SetNormal(vector3());
  }
  else if (key == "vup")
  {
    SetBitExact(
      vector3(),
      [&](const GeometryType::VectorType & v) { geometry->SetViewUp(v); },
      [&]() { return geometry->GetViewUp(); });
  }
  else if (key == "isocenter")
  {
    const GeometryType::VectorType v = vector3();
    GeometryType::PointType        p;
    p[0] = v[0];
    p[1] = v[1];
    p[2] = v[2];
    SetBitExact(
      p,
      [&](const GeometryType::PointType & v) { geometry->SetIsocenter(v); },
      [&]() { return geometry->GetIsocenter(); });
  }
  else if (key == "cols" || key == "rows")
  {
    expect(1);
    GeometryType::DetectorSizeType size = geometry->GetDetectorSize();
    size[key == "cols" ? 0 : 1] = ParseCount(values[0], key, where);
    geometry->SetDetectorSize(size);
  }
  else if (key == "spacing")
  {
    SetBitExact(
      vector2(),
      [&](const GeometryType::DetectorVectorType & v) { geometry->SetDetectorSpacing(v); },
      [&]() { return geometry->GetDetectorSpacing(); });
  }
  else if (key == "offset")
  {
    SetBitExact(
      vector2(),
      [&](const GeometryType::DetectorVectorType & v) { geometry->SetDetectorOffset(v); },
      [&]() { return geometry->GetDetectorOffset(); });
  }
  else if (key == "mirror")
  {
    expect(1);
    if (values[0] != "0" && values[0] != "1")
    {
      ThrowGeometryError(where + "mirror must be 0 or 1, got '" + values[0] + "'");
    }
    geometry->SetColumnsMirrored(values[0] == "1");
  }
  else
  {
    ThrowGeometryError(
      where + "unknown key '" + key +
      "' (known: projection, sad, sid, gantry, nrm, vup, isocenter, cols, rows, spacing, offset, mirror)");
  }
}

/** True if the reader reads text back as value, bit for bit. */
bool
ReadsBackAs(const std::string & text, double value)
{
  double readBack = 0.0;
  return DRRNumberParser::ParseFiniteNumber(text, readBack) && std::memcmp(&readBack, &value, sizeof(double)) == 0;
}

/** The shortest decimal form that reads back to the same double, or else (a subnormal number, whose decimal form
 * strtod() reads with ERANGE, which the reader refuses) the exact hexadecimal one; throws for a non-finite value. */
std::string
FormatNumber(double value, const char * key)
{
  if (!std::isfinite(value))
  {
    ThrowWriteError(std::string("the value of key '") + key + "' is not finite: the reader would refuse it");
  }
  char        buffer[64];
  const auto  result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  std::string text(buffer, result.ptr);
  if (!ReadsBackAs(text, value))
  {
    std::snprintf(buffer, sizeof(buffer), "%a", value);
    text = buffer;
    if (!ReadsBackAs(text, value))
    {
      ThrowWriteError(std::string("the value ") + text + " of key '" + key + "' does not read back");
    }
  }
  return text;
}

template <typename TVector>
std::string
FormatNumbers(const TVector & values, unsigned int count, const char * key)
{
  std::string text;
  for (unsigned int d = 0; d < count; ++d)
  {
    text += (d == 0 ? "" : " ") + FormatNumber(values[d], key);
  }
  return text;
}

std::string
FormatCount(SizeValueType count, const char * key)
{
  if (!DRRNumberParser::IsWholeNumberInRange(static_cast<double>(count), 1.0, 1e6))
  {
    ThrowWriteError(std::string("key '") + key + "' is " + std::to_string(count) +
                    ", outside [1, 1e6]: the reader would refuse it");
  }
  return std::to_string(count);
}
} // namespace

void
DRRProjectionGeometryFileIO::Read(GeometryType * geometry)
{
  CheckGeometry(geometry);
  // A directory opens as a stream that reads nothing, which would leave the defaults in place: refuse it.
  std::error_code error;
  if (std::filesystem::is_directory(m_FileName, error))
  {
    ThrowGeometryError("cannot read geometry file '" + m_FileName + "': it is a directory");
  }
  std::ifstream file(m_FileName);
  if (!file)
  {
    ThrowGeometryError("cannot open geometry file '" + m_FileName + "'");
  }
  ReadFromStream(file, geometry, m_FileName);
}

void
DRRProjectionGeometryFileIO::Write(const GeometryType * geometry)
{
  CheckGeometry(geometry);
  std::ostringstream text;
  WriteToStream(text, geometry);
  std::ofstream file(m_FileName, std::ios::out | std::ios::trunc);
  file << text.str();
  file.close(); // a short write or a failed close (a full disk) leaves the stream failed
  if (!file)
  {
    ThrowWriteError("cannot write geometry file '" + m_FileName + "'");
  }
}

void
DRRProjectionGeometryFileIO::ReadFromStream(std::istream &      stream,
                                            GeometryType *      geometry,
                                            const std::string & sourceName)
{
  CheckGeometry(geometry);
  const std::string prefix = sourceName.empty() ? std::string("line ") : sourceName + ":";
  std::string       line;
  for (unsigned int lineNumber = 1; std::getline(stream, line); ++lineNumber)
  {
    ParseLine(line, geometry, prefix + std::to_string(lineNumber) + ": ");
  }
}

void
DRRProjectionGeometryFileIO::WriteToStream(std::ostream & stream, const GeometryType * geometry)
{
  CheckGeometry(geometry);
  // The normal SetGantryAngleInDegrees() gives, computed by it: `nrm` follows only if the normal in force differs.
  const auto gantry = GeometryType::New();
  gantry->SetGantryAngleInDegrees(geometry->GetGantryAngleInDegrees());
  const auto & normal = geometry->GetNormal();
  bool         writeNormal = false;
  for (unsigned int d = 0; d < 3; ++d)
  {
    // Bit for bit: 0 and -0 differ (gantry 0 gives the normal (1, -0, 0)).
    writeNormal = writeNormal || !(gantry->GetNormal()[d] == normal[d]) ||
                  std::signbit(gantry->GetNormal()[d]) != std::signbit(normal[d]);
  }

  // Format everything first, so that a refused value writes nothing.
  std::ostringstream text;
  text << "# PointBasedDRR projection geometry (lengths in mm, angles in degrees)\n";
  text << "projection " << DRRPolicies::Beams::GetName(geometry->GetProjection()) << '\n';
  text << "sad " << FormatNumber(geometry->GetSourceToIsocenterDistance(), "sad") << '\n';
  text << "sid " << FormatNumber(geometry->GetSourceToDetectorDistance(), "sid") << '\n';
  text << "gantry " << FormatNumber(geometry->GetGantryAngleInDegrees(), "gantry") << '\n';
  if (writeNormal)
  {
    text << "nrm " << FormatNumbers(normal, 3, "nrm") << '\n';
  }
  text << "vup " << FormatNumbers(geometry->GetViewUp(), 3, "vup") << '\n';
  text << "isocenter " << FormatNumbers(geometry->GetIsocenter(), 3, "isocenter") << '\n';
  text << "cols " << FormatCount(geometry->GetDetectorSize()[0], "cols") << '\n';
  text << "rows " << FormatCount(geometry->GetDetectorSize()[1], "rows") << '\n';
  text << "spacing " << FormatNumbers(geometry->GetDetectorSpacing(), 2, "spacing") << '\n';
  text << "offset " << FormatNumbers(geometry->GetDetectorOffset(), 2, "offset") << '\n';
  text << "mirror " << (geometry->GetColumnsMirrored() ? 1 : 0) << '\n';
  stream << text.str();
}

void
DRRProjectionGeometryFileIO::ParseLine(const std::string & rawLine, GeometryType * geometry, const std::string & where)
{
  CheckGeometry(geometry);
  const std::string        line = rawLine.substr(0, rawLine.find('#'));
  std::istringstream       stream(line);
  std::string              key;
  std::vector<std::string> values;
  if (!(stream >> key))
  {
    return; // blank or comment-only line
  }
  for (std::string token; stream >> token;)
  {
    values.push_back(token);
  }
  try
  {
    ApplyKey(geometry, key, values, where);
  }
  catch (const ExceptionObject & e)
  {
    const std::string message = e.GetDescription();
    if (where.empty() || message.find(where) != std::string::npos)
    {
      throw;
    }
    ThrowGeometryError(where + "key '" + key + "': " + message);
  }
}

void
DRRProjectionGeometryFileIO::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << m_FileName << std::endl;
}
} // namespace itk
