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

// libFuzzer target: the bytes decode into a small volume, a geometry, an optional transform and the settings of the
// filters; itk::PointBasedDRRImageFilter and itk::ExactDRRImageFilter render it (docs/fuzzing.md).
//
// An itk::ExceptionObject is a valid outcome (bad input may be refused). Findings (abort, printing the decoded case):
// any other exception, a crash or a sanitizer report, a non-finite output pixel or standard error, a negative line
// integral or standard error, a transmission outside [0, 1] or a gray level outside its range, and anything but an
// exact zero image (zero standard error) from a volume whose every voxel has zero attenuation.
//
// Decoding: every decision is one FuzzedDataProvider::ConsumeIntegralInRange() (bytes taken from the end of the data,
// most significant first); a real number is a one-byte index into a table of values worth trying, or past the table a
// 16-bit fraction of a range. test/fuzz/corpus/make_filter_seeds.py writes seeds in this encoding and must follow the
// order of the decisions below. With PBDRR_FUZZ_PRINT=1 in the environment every decoded case is printed.

#include "itkAffineTransform.h"
#include "itkDRRPolicies.h"
#include "itkDRRSamplerFactory.h"
#include "itkEuler3DTransform.h"
#include "itkExactDRRImageFilter.h"
#include "itkImage.h"
#include "itkPlatformMultiThreader.h"
#include "itkPointBasedDRRImageFilter.h"

#include <fuzzer/FuzzedDataProvider.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace
{
using ProjectionType = itk::Image<float, 2>;
using GeometryType = itk::DRRProjectionGeometry;
using PointType = GeometryType::PointType;
using VectorType = GeometryType::VectorType;
using Enums = itk::PointBasedDRREnums;

constexpr double inf = std::numeric_limits<double>::infinity();
constexpr double nan = std::numeric_limits<double>::quiet_NaN();
constexpr double degree = 0.017453292519943295;

// Tables of values worth trying; entry 0 is what an exhausted input decodes to.
const std::vector<double> spacings = { 1.0, 0.5, 2.5, 1e-6, 1e-3, 0.1, 10.0, 1e3, 1e6, 1e9, -1.0, 0.7 };
const std::vector<double> origins = { 0.0, -100.0, 100.0, 1e7, -1e9, 0.5 };
const std::vector<double> angles = { 0.0, 90.0, 180.0, 270.0, 45.0, -30.0, 360.0, 1e9, 1e20, 0.001 };
const std::vector<double> unitComponents = { 0.0, 1.0, -1.0, 1e-300, 1e300, 0.5 };
const std::vector<double> shortSpecials = { 0.0,    1000.0, -1000.0, -1024.0, -3024.0, 3071.0,
                                            32767., -32768, -1.0,    1.0,     2000.0,  -500.0 };
const std::vector<double> floatSpecials = { 0.02, 0.0,  nan, inf,  -inf,   -0.0,    1e-30, 1e30,
                                            3e38, -1.0, 1e3, -1e3, 3071.0, -3024.0, 1e-45, 0.5 };
const std::vector<double> distances = { 1000.0, 1e-6, 1e-3, 0.5, 10.0, 100.0, 1e4, 1e7, 1e8, 0.0, -100.0, 5.0 };
const std::vector<double> factors = { 1.5, 1.0, 2.0, 0.5, 1e-3, 1e3, 0.0, 1e-9 };
const std::vector<double> lengths = { 0.0, 1.0, -1.0, 10.0, -50.0, 1e4, 1e7, -1e8 };
const std::vector<double> detectorSpacings = { 1.0, 1e-6, 0.01, 0.1, 10.0, 1e3, 1e7, 2e7, 0.0, -1.0 };

/** Reads the decisions of one case from the fuzzer's bytes and writes each one, named, into a trace. */
class Reader
{
public:
  Reader(const uint8_t * data, size_t size) : m_Provider(data, size) {}

  unsigned
  Choice(const char * name, unsigned count)
  {
    const unsigned value = m_Provider.ConsumeIntegralInRange<unsigned>(0, count - 1);
    m_Trace << name << '=' << value << ' ';
    return value;
  }

  bool
  Flag(const char * name)
  {
    return this->Choice(name, 2) == 1;
  }

  /** An entry of the table, or past it a 16-bit fraction of [low, high]. */
  double
  Real(const char * name, const std::vector<double> & table, double low, double high)
  {
    const unsigned index = m_Provider.ConsumeIntegralInRange<unsigned>(0, 255);
    double         value = 0.0;
    if (index < table.size())
    {
      value = table[index];
    }
    else
    {
      value = low + (high - low) * m_Provider.ConsumeIntegralInRange<unsigned>(0, 65535) / 65535.0;
    }
    m_Trace << name << '=' << value << ' ';
    return value;
  }

  /** Not traced: the caller notes what it makes of it. */
  unsigned
  Raw(unsigned count)
  {
    return m_Provider.ConsumeIntegralInRange<unsigned>(0, count - 1);
  }

  int
  Short()
  {
    return m_Provider.ConsumeIntegralInRange<int>(-32768, 32767);
  }

  void
  Note(const std::string & text)
  {
    m_Trace << text << ' ';
  }

  std::string
  Trace() const
  {
    return m_Trace.str();
  }

private:
  FuzzedDataProvider m_Provider;
  std::ostringstream m_Trace;
};

[[noreturn]] void
Finding(const std::string & what, const Reader & reader)
{
  std::cerr << "PointBasedDRRFilterFuzzer finding: " << what << "\ndecoded case: " << reader.Trace() << std::endl;
  std::abort();
}

/** A voxel value: a special value, or a random short or real. */
double
Voxel(Reader & reader, bool floatVoxels)
{
  if (floatVoxels)
  {
    return reader.Real("v", floatSpecials, -1100.0, 3100.0);
  }
  const unsigned index = reader.Raw(256);
  const double   value = index < shortSpecials.size() ? shortSpecials[index] : static_cast<double>(reader.Short());
  reader.Note("v=" + std::to_string(static_cast<int>(value)));
  return value;
}

using MatrixType = itk::Matrix<double, 3, 3>;

MatrixType
Rotation(double a, double b, double c)
{
  auto euler = itk::Euler3DTransform<double>::New();
  euler->SetRotation(a * degree, b * degree, c * degree);
  return euler->GetMatrix();
}

MatrixType
DecodeDirection(Reader & reader)
{
  MatrixType direction;
  direction.SetIdentity();
  switch (reader.Choice("direction", 6))
  {
    case 0:
      break;
    case 1: // an axis permutation with signs, right- or left-handed
    {
      const unsigned code = reader.Choice("permutation", 48);
      const unsigned permutations[6][3] = {
        { 0, 1, 2 }, { 0, 2, 1 }, { 1, 0, 2 }, { 1, 2, 0 }, { 2, 0, 1 }, { 2, 1, 0 }
      };
      direction.Fill(0.0);
      for (unsigned c = 0; c < 3; ++c)
      {
        direction[permutations[code % 6][c]][c] = ((code / 6) >> c) & 1 ? -1.0 : 1.0;
      }
      break;
    }
    case 2: // a rotation
    case 3: // a rotation followed by a flip of one axis: left-handed
    {
      const double a = reader.Real("a", angles, -180.0, 180.0);
      const double b = reader.Real("b", angles, -180.0, 180.0);
      const double c = reader.Real("c", angles, -180.0, 180.0);
      direction = Rotation(a, b, c);
      if (reader.Flag("flip"))
      {
        for (unsigned r = 0; r < 3; ++r)
        {
          direction[r][0] = -direction[r][0];
        }
      }
      break;
    }
    case 4: // anything: not orthogonal, maybe singular
    {
      for (unsigned r = 0; r < 3; ++r)
      {
        for (unsigned c = 0; c < 3; ++c)
        {
          direction[r][c] = reader.Real("d", unitComponents, -1.0, 1.0);
        }
      }
      break;
    }
    case 5: // nearly singular: two columns almost parallel
    {
      const double epsilon = reader.Real("epsilon", { 1e-9, 1e-15, 1e-300, 0.0 }, 0.0, 1e-3);
      direction[0][1] = 1.0;
      direction[1][1] = epsilon;
      break;
    }
  }
  return direction;
}

template <typename TVolume>
typename TVolume::Pointer
DecodeVolume(Reader & reader, bool floatVoxels)
{
  typename TVolume::SizeType size;
  for (unsigned a = 0; a < 3; ++a)
  {
    size[a] = 1 + reader.Choice("size-1", 8);
  }
  typename TVolume::SpacingType spacing;
  for (unsigned a = 0; a < 3; ++a)
  {
    spacing[a] = reader.Real("spacing", spacings, 0.05, 5.0);
  }
  typename TVolume::PointType origin;
  for (unsigned a = 0; a < 3; ++a)
  {
    origin[a] = reader.Real("origin", origins, -500.0, 500.0);
  }
  const MatrixType direction = DecodeDirection(reader);

  auto volume = TVolume::New();
  volume->SetRegions(size);
  volume->Allocate();
  const size_t count = volume->GetLargestPossibleRegion().GetNumberOfPixels();
  auto *       buffer = volume->GetBufferPointer();
  using PixelType = typename TVolume::PixelType;
  const unsigned fill = reader.Choice("fill", 4);
  if (fill == 0) // one value
  {
    std::fill(buffer, buffer + count, static_cast<PixelType>(Voxel(reader, floatVoxels)));
  }
  else if (fill == 1) // every voxel its own value
  {
    for (size_t i = 0; i < count; ++i)
    {
      buffer[i] = static_cast<PixelType>(Voxel(reader, floatVoxels));
    }
  }
  else if (fill == 2) // a block in a background
  {
    const auto background = static_cast<PixelType>(Voxel(reader, floatVoxels));
    const auto block = static_cast<PixelType>(Voxel(reader, floatVoxels));
    std::fill(buffer, buffer + count, background);
    itk::Index<3> low, high;
    for (unsigned a = 0; a < 3; ++a)
    {
      low[a] = reader.Choice("low", size[a]);
      high[a] = reader.Choice("high", size[a]);
    }
    for (itk::IndexValueType z = low[2]; z <= high[2]; ++z)
    {
      for (itk::IndexValueType y = low[1]; y <= high[1]; ++y)
      {
        for (itk::IndexValueType x = low[0]; x <= high[0]; ++x)
        {
          buffer[x + size[0] * (y + size[1] * z)] = block;
        }
      }
    }
  }
  else // a checkerboard of two values
  {
    const auto even = static_cast<PixelType>(Voxel(reader, floatVoxels));
    const auto odd = static_cast<PixelType>(Voxel(reader, floatVoxels));
    for (size_t i = 0; i < count; ++i)
    {
      const size_t x = i % size[0], y = (i / size[0]) % size[1], z = i / (size[0] * size[1]);
      buffer[i] = (x + y + z) % 2 ? odd : even;
    }
  }
  // ITK refuses some of these itself (a singular direction or spacing): an itk::ExceptionObject, a valid outcome. It
  // inverts direction x spacing by netlib's SVD, which spins for minutes on entries whose squares overflow or
  // underflow (a fuzz input timed out inside ITK's SetDirection): such a grid is refused here, as ITK would have to.
  for (unsigned r = 0; r < 3; ++r)
  {
    for (unsigned c = 0; c < 3; ++c)
    {
      const double entry = std::abs(direction[r][c] * spacing[c]);
      if (!(entry <= 1e150) || (entry > 0.0 && entry < 1e-150))
      {
        itkGenericExceptionMacro("a direction x spacing entry of " << entry << " is beyond what ITK's SVD inverts");
      }
    }
  }
  volume->SetSpacing(spacing);
  volume->SetOrigin(origin);
  volume->SetDirection(direction);
  return volume;
}

void
DecodeTransferFunction(Reader & reader, itk::DRRTransferFunction * transfer)
{
  switch (reader.Choice("transfer", 5))
  {
    case 0:
      break;
    case 1:
      transfer->SetMuWaterPerMillimeter(
        reader.Real("muWater", { 0.02059, 0.0, -1.0, 1e-9, 10.0, 11.0, 1e-300, nan }, 1e-4, 1.0));
      break;
    case 2:
      transfer->SetEffectiveEnergyInKeV(reader.Real("keV", { 60.0, 10.0, 1000.0, 9.9, 1001.0, 50.0 }, 10.0, 1000.0));
      break;
    case 3:
      transfer->SetMode(Enums::TransferFunction::Identity);
      break;
    case 4:
    {
      itk::DRRTransferFunction::PointListType points;
      const unsigned                          count = 1 + reader.Choice("points-1", 4);
      double                                  value = -1000.0;
      for (unsigned i = 0; i < count; ++i)
      {
        value += reader.Real("step", { 500.0, 0.0, -1.0, 1e-12, 1e6 }, 0.0, 2000.0);
        points.emplace_back(value, reader.Real("mu", { 0.02, 0.0, 1e-30, 1e30, -0.01, nan }, 0.0, 0.1));
      }
      transfer->SetPiecewiseLinearPoints(points);
      break;
    }
  }
  if (reader.Flag("airThreshold"))
  {
    transfer->SetAirThreshold(reader.Real("threshold", { -999.5, -1000.0, 0.0, 1e30, -1e30, nan, inf }, -2000., 4000.));
  }
}

struct VolumeBox
{
  PointType Centre;
  double    Radius; // half the diagonal of the bounding box of the voxels
};

template <typename TVolume>
VolumeBox
Bounds(const TVolume * volume)
{
  const auto size = volume->GetLargestPossibleRegion().GetSize();
  double     low[3] = { inf, inf, inf }, high[3] = { -inf, -inf, -inf };
  for (unsigned corner = 0; corner < 8; ++corner)
  {
    itk::ContinuousIndex<double, 3> index;
    for (unsigned a = 0; a < 3; ++a)
    {
      index[a] = (corner >> a) & 1 ? static_cast<double>(size[a]) - 0.5 : -0.5;
    }
    PointType p;
    volume->TransformContinuousIndexToPhysicalPoint(index, p);
    for (unsigned a = 0; a < 3; ++a)
    {
      low[a] = std::min(low[a], p[a]);
      high[a] = std::max(high[a], p[a]);
    }
  }
  VolumeBox box;
  double    squared = 0.0;
  for (unsigned a = 0; a < 3; ++a)
  {
    box.Centre[a] = 0.5 * (low[a] + high[a]);
    squared += (high[a] - low[a]) * (high[a] - low[a]);
  }
  box.Radius = 0.5 * std::sqrt(squared);
  return box;
}

VectorType
Vec(double x, double y, double z)
{
  VectorType v;
  v[0] = x;
  v[1] = y;
  v[2] = z;
  return v;
}

void
DecodeGeometry(Reader & reader, GeometryType * geometry, const VolumeBox & box)
{
  const unsigned kind = reader.Choice("geometry", 4);
  const bool     parallel = kind == 1 || kind == 3;
  double         magnification = 1.0;
  if (kind <= 1) // plastimatch's parameters
  {
    geometry->SetProjection(parallel ? Enums::Projection::Parallel : Enums::Projection::Perspective);
    PointType isocenter = box.Centre;
    switch (reader.Choice("isocenter", 3))
    {
      case 0:
        break;
      case 1:
        for (unsigned a = 0; a < 3; ++a)
        {
          isocenter[a] += box.Radius * reader.Real("shift", { 0.0, 1.0, -1.0, 0.5 }, -2.0, 2.0);
        }
        break;
      case 2:
        for (unsigned a = 0; a < 3; ++a)
        {
          isocenter[a] = reader.Real("iso", { 0.0, 1e7, -1e7, 1e8, nan }, -1000.0, 1000.0);
        }
        break;
    }
    geometry->SetIsocenter(isocenter);
    const unsigned normal = reader.Choice("normal", 3);
    if (normal != 1)
    {
      geometry->SetGantryAngleInDegrees(reader.Real("gantry", angles, -720.0, 720.0));
    }
    if (normal != 0)
    {
      const double x = reader.Real("nx", unitComponents, -1.0, 1.0);
      const double y = reader.Real("ny", unitComponents, -1.0, 1.0);
      const double z = reader.Real("nz", unitComponents, -1.0, 1.0);
      geometry->SetNormal(Vec(x, y, z));
    }
    if (reader.Flag("vup"))
    {
      const double x = reader.Real("ux", unitComponents, -1.0, 1.0);
      const double y = reader.Real("uy", unitComponents, -1.0, 1.0);
      const double z = reader.Real("uz", unitComponents, -1.0, 1.0);
      geometry->SetViewUp(Vec(x, y, z));
    }
    double sad = 0.0;
    if (reader.Flag("sourceInside")) // the source within the volume's bounding sphere, or on its centre
    {
      sad = box.Radius * reader.Real("sadOverRadius", { 0.5, 0.0, 1e-9, 0.99, 1.0, 1.01 }, 0.0, 2.0);
    }
    else
    {
      sad = std::max(box.Radius, 1.0) * reader.Real("sadOverRadius", { 10.0, 2.0, 1.5, 100.0, 1e4 }, 1.0, 50.0);
      if (reader.Flag("sadGiven"))
      {
        sad = reader.Real("sad", distances, 1.0, 2000.0);
      }
    }
    double sid = 1.5 * sad;
    switch (reader.Choice("sid", 3))
    {
      case 0:
        break;
      case 1:
        sid = sad * reader.Real("sidOverSad", factors, 0.01, 4.0);
        break;
      case 2:
        sid = reader.Real("sid", distances, 1.0, 3000.0);
        break;
    }
    geometry->SetSourceToIsocenterDistance(sad);
    geometry->SetSourceToDetectorDistance(sid);
    if (!parallel && sad > 0.0)
    {
      magnification = std::min(sid / sad, 1e6);
    }
  }
  else // the explicit forms: a rotated detector frame
  {
    const double a = reader.Real("a", angles, -180.0, 180.0);
    const double b = reader.Real("b", angles, -180.0, 180.0);
    const double c = reader.Real("c", angles, -180.0, 180.0);
    const auto   rotation = Rotation(a, b, c);
    VectorType   u = Vec(rotation[0][0], rotation[1][0], rotation[2][0]);
    VectorType   v = Vec(rotation[0][1], rotation[1][1], rotation[2][1]);
    if (reader.Flag("skew"))
    {
      u += v * reader.Real("skewBy", { 1e-7, 1e-5, 1.0 }, 0.0, 1e-3);
    }
    const VectorType n = Vec(v[1] * u[2] - v[2] * u[1], v[2] * u[0] - v[0] * u[2], v[0] * u[1] - v[1] * u[0]);
    const double     distance =
      std::max(box.Radius, 1.0) * reader.Real("distance", { 3.0, 0.0, 0.5, 1e-9, 1e4, -3.0 }, -5.0, 50.0);
    if (parallel)
    {
      geometry->SetExplicitParallelGeometry(box.Centre - n * distance, u, v);
    }
    else
    {
      const PointType source = box.Centre + n * distance;
      const double    sid = std::max(box.Radius, 1.0) * reader.Real("sidOverRadius", { 6.0, 1.0, 1e-6, 0.0 }, 0., 50.);
      geometry->SetExplicitPerspectiveGeometry(source, source - n * sid, u, v);
      magnification = distance > 0.0 ? std::min(sid / distance, 1e6) : 1.0;
    }
  }

  GeometryType::DetectorSizeType size;
  size[0] = 1 + reader.Choice("cols-1", 16);
  size[1] = 1 + reader.Choice("rows-1", 16);
  geometry->SetDetectorSize(size);
  GeometryType::DetectorVectorType spacing;
  switch (reader.Choice("detectorSpacing", 3))
  {
    case 0: // the detector sees the volume's bounding sphere, a little more
      for (unsigned d = 0; d < 2; ++d)
      {
        spacing[d] = std::min(std::max(2.2 * box.Radius * magnification / size[d], 1e-6), 1e7);
      }
      break;
    case 1:
      spacing[0] = reader.Real("du", detectorSpacings, 0.05, 50.0);
      spacing[1] = reader.Real("dv", detectorSpacings, 0.05, 50.0);
      break;
    case 2:
      spacing.Fill(reader.Real("duv", detectorSpacings, 0.05, 50.0));
      break;
  }
  geometry->SetDetectorSpacing(spacing);
  if (reader.Flag("offset"))
  {
    GeometryType::DetectorVectorType offset;
    offset[0] = reader.Real("offU", lengths, -100.0, 100.0);
    offset[1] = reader.Real("offV", lengths, -100.0, 100.0);
    geometry->SetDetectorOffset(offset);
  }
}

itk::Transform<double, 3, 3>::Pointer
DecodeTransform(Reader & reader, const VolumeBox & box)
{
  switch (reader.Choice("transform", 3))
  {
    case 1:
    {
      auto euler = itk::Euler3DTransform<double>::New();
      euler->SetCenter(box.Centre);
      const double a = reader.Real("ra", angles, -180.0, 180.0);
      const double b = reader.Real("rb", angles, -180.0, 180.0);
      const double c = reader.Real("rc", angles, -180.0, 180.0);
      euler->SetRotation(a * degree, b * degree, c * degree);
      itk::Euler3DTransform<double>::OutputVectorType translation;
      for (unsigned d = 0; d < 3; ++d)
      {
        translation[d] = reader.Real("t", lengths, -20.0, 20.0);
      }
      euler->SetTranslation(translation);
      return euler.GetPointer();
    }
    case 2:
    {
      auto affine = itk::AffineTransform<double, 3>::New();
      affine->SetCenter(box.Centre);
      itk::AffineTransform<double, 3>::MatrixType matrix;
      for (unsigned r = 0; r < 3; ++r)
      {
        for (unsigned c = 0; c < 3; ++c)
        {
          matrix[r][c] = r == c ? 1.0 : 0.0;
          matrix[r][c] += reader.Real("m", { 0.0, 1.0, -1.0, -2.0, 1e-9, 1e9, -1e-300 }, -1.0, 1.0);
        }
      }
      affine->SetMatrix(matrix);
      itk::AffineTransform<double, 3>::OutputVectorType translation;
      for (unsigned d = 0; d < 3; ++d)
      {
        translation[d] = reader.Real("t", lengths, -20.0, 20.0);
      }
      affine->SetTranslation(translation);
      return affine.GetPointer();
    }
    default:
      return nullptr;
  }
}

/** The settings of the renders, decoded once and applied to both filters. */
struct Settings
{
  unsigned                              Sampler{ 0 };
  Enums::ReconstructionKernel           Kernel{ Enums::ReconstructionKernel::Box };
  Enums::Splat                          Splat{ Enums::Splat::Nearest };
  Enums::PointWeighting                 Weighting{ Enums::PointWeighting::Unbiased };
  unsigned                              Strata{ 0 };
  uint64_t                              Seed{ 0 };
  uint64_t                              Samples{ 1000 };
  Enums::OutputMode                     OutputMode{ Enums::OutputMode::LineIntegral };
  double                                WindowLevel{ 0.0 };
  double                                WindowWidth{ 0.0 };
  bool                                  Reuse{ false };
  unsigned                              Threads{ 1 };
  unsigned                              RaysPerPixelSide{ 1 };
  uint64_t                              RefineSamples{ 0 };
  double                                SecondPoseGantry{ 0.0 };
  bool                                  UnsignedCharOutput{ false };
  itk::Transform<double, 3, 3>::Pointer Transform;
};

Settings
DecodeSettings(Reader & reader)
{
  Settings     s;
  const auto & samplers = itk::DRRSamplerFactory::GetEntries();
  s.Sampler = reader.Choice("sampler", static_cast<unsigned>(samplers.size()));
  reader.Note("(" + samplers[s.Sampler].Name + ")");
  // Every registered kernel and splat, by its index in the registry (with two of each, the same byte as a flag).
  const auto kernels = itk::DRRPolicies::Kernels::GetEntries();
  s.Kernel = kernels[reader.Choice("kernel", static_cast<unsigned>(kernels.size()))].Id;
  reader.Note("(" + itk::DRRPolicies::Kernels::GetName(s.Kernel) + ")");
  const auto splats = itk::DRRPolicies::Splats::GetEntries();
  s.Splat = splats[reader.Choice("splat", static_cast<unsigned>(splats.size()))].Id;
  reader.Note("(" + itk::DRRPolicies::Splats::GetName(s.Splat) + ")");
  s.Weighting = reader.Flag("paperCount") ? Enums::PointWeighting::PaperCount : Enums::PointWeighting::Unbiased;
  const unsigned strata = reader.Choice("strataKind", 4);
  s.Strata = strata == 0 ? 0 : strata == 1 ? 2 : strata == 2 ? 256 : 2 + reader.Choice("strata-2", 255);
  s.Seed = reader.Choice("seed", 65536);
  const unsigned samples = reader.Choice("samplesKind", 4);
  s.Samples = samples == 0 ? 1000 : samples == 1 ? 1 : samples == 2 ? 5000 : 1 + reader.Choice("samples-1", 5000);
  s.OutputMode = static_cast<Enums::OutputMode>(reader.Choice("outputMode", 4));
  if (reader.Flag("window"))
  {
    s.WindowLevel = reader.Real("level", { 1.0, 0.0, -1.0, nan, inf, 1e300 }, -5.0, 5.0);
    s.WindowWidth = reader.Real("width", { 2.0, 0.0, -1.0, nan, inf, 1e-300 }, 0.0, 10.0);
  }
  s.Reuse = reader.Flag("reuse");
  s.Threads = 1 + reader.Choice("threads-1", 3);
  s.RaysPerPixelSide = 1 + reader.Choice("raysPerPixelSide-1", 2);
  if (reader.Flag("refine"))
  {
    s.RefineSamples = 1 + reader.Choice("refineSamples-1", 2000);
  }
  if (s.Reuse)
  {
    s.SecondPoseGantry = reader.Real("secondPoseGantry", { 10.0, 0.0, 180.0, 1e-9 }, -90.0, 90.0);
  }
  s.UnsignedCharOutput = reader.Flag("unsignedCharOutput"); // holds the Gray8 mode only
  return s;
}

/** Checks both outputs: finite, within the range of the output mode; exactly empty for a volume without attenuation. */
template <typename TProjection>
void
CheckOutputs(const TProjection * image,
             const TProjection * standardError,
             Enums::OutputMode   mode,
             bool                zeroAttenuation,
             const char *        filterName,
             const Reader &      reader)
{
  const size_t count = image->GetBufferedRegion().GetNumberOfPixels();
  if (count != image->GetLargestPossibleRegion().GetNumberOfPixels() || count == 0)
  {
    Finding(std::string(filterName) + ": the output is not fully buffered", reader);
  }
  using PixelType = typename TProjection::PixelType;
  const PixelType * values = image->GetBufferPointer();
  const PixelType * errors = standardError ? standardError->GetBufferPointer() : nullptr;
  const double      maximum = mode == Enums::OutputMode::Gray8          ? 255.0
                              : mode == Enums::OutputMode::Gray16       ? 65535.0
                              : mode == Enums::OutputMode::Transmission ? 1.0
                                                                        : inf;
  for (size_t p = 0; p < count; ++p)
  {
    std::ostringstream where;
    const double       value = static_cast<double>(values[p]);
    const double       error = errors ? static_cast<double>(errors[p]) : 0.0;
    where << filterName << ", pixel " << p << ": value " << value;
    if (errors)
    {
      where << ", standard error " << error;
    }
    if (!std::isfinite(value) || !(value >= 0.0) || !(value <= maximum))
    {
      Finding(where.str() + ": the value is not finite or outside [0, " + std::to_string(maximum) + "]", reader);
    }
    if (!std::isfinite(error) || !(error >= 0.0))
    {
      Finding(where.str() + ": the standard error is not finite and non-negative", reader);
    }
    if (zeroAttenuation)
    {
      const double expected = mode == Enums::OutputMode::Transmission ? 1.0 : 0.0;
      if ((mode == Enums::OutputMode::LineIntegral || mode == Enums::OutputMode::Transmission) && value != expected)
      {
        Finding(where.str() + ": every voxel has zero attenuation, yet the value is not exactly " +
                  std::to_string(expected),
                reader);
      }
      if (error != 0.0)
      {
        Finding(where.str() + ": every voxel has zero attenuation, yet the standard error is not 0", reader);
      }
    }
  }
}

template <typename TFilter>
void
UseThreads(TFilter * filter, unsigned threads)
{
  auto threader = itk::PlatformMultiThreader::New();
  threader->SetMaximumNumberOfThreads(threads);
  threader->SetNumberOfWorkUnits(threads);
  filter->SetMultiThreader(threader);
  filter->SetNumberOfWorkUnits(threads);
}

/** Runs one filter; an itk::ExceptionObject is a refusal (returns false), any other exception a finding. */
template <typename TCall>
bool
Accepted(TCall && call, const char * what, const Reader & reader)
{
  try
  {
    call();
    return true;
  }
  catch (const itk::ExceptionObject &)
  {
    return false;
  }
  catch (const std::exception & e)
  {
    Finding(std::string(what) + " threw a std::exception that is not an itk::ExceptionObject: " + e.what(), reader);
  }
  catch (...)
  {
    Finding(std::string(what) + " threw something that is not an exception", reader);
  }
}

template <typename TVolume, typename TProjection>
void
Render(const Reader &             reader,
       TVolume *                  volume,
       itk::DRRTransferFunction * transfer,
       GeometryType *             geometry,
       const Settings &           settings,
       bool                       zeroAttenuation);

template <typename TVolume>
void
RunCase(Reader & reader, bool floatVoxels)
{
  typename TVolume::Pointer volume;
  if (!Accepted([&] { volume = DecodeVolume<TVolume>(reader, floatVoxels); }, "building the volume", reader))
  {
    return;
  }
  const VolumeBox box = Bounds(volume.GetPointer());
  if (!std::isfinite(box.Radius) || !std::isfinite(box.Centre[0]) || !std::isfinite(box.Centre[1]) ||
      !std::isfinite(box.Centre[2]))
  {
    reader.Note("(volume bounds not finite)");
  }
  auto transfer = itk::DRRTransferFunction::New();
  auto geometry = GeometryType::New();
  if (!Accepted([&] { DecodeTransferFunction(reader, transfer); }, "the transfer function", reader) ||
      !Accepted([&] { DecodeGeometry(reader, geometry, box); }, "the geometry", reader))
  {
    return;
  }
  Settings settings;
  if (!Accepted(
        [&] {
          settings = DecodeSettings(reader);
          settings.Transform = DecodeTransform(reader, box);
        },
        "the settings",
        reader))
  {
    return;
  }
  if (std::getenv("PBDRR_FUZZ_PRINT"))
  {
    std::cerr << "case: " << reader.Trace() << std::endl;
  }

  // Zero attenuation everywhere: every voxel is finite and maps to mu = 0 (a volume the filters accept).
  bool         zeroAttenuation = true;
  const auto * buffer = volume->GetBufferPointer();
  for (size_t i = 0; i < volume->GetLargestPossibleRegion().GetNumberOfPixels(); ++i)
  {
    const double value = static_cast<double>(buffer[i]);
    zeroAttenuation = zeroAttenuation && std::isfinite(value) && transfer->Evaluate(value) == 0.0;
  }

  if (settings.UnsignedCharOutput)
  {
    Render<TVolume, itk::Image<unsigned char, 2>>(reader, volume, transfer, geometry, settings, zeroAttenuation);
  }
  else
  {
    Render<TVolume, ProjectionType>(reader, volume, transfer, geometry, settings, zeroAttenuation);
  }
}

/** Renders the case with both filters and checks their outputs. */
template <typename TVolume, typename TProjection>
void
Render(const Reader &             reader,
       TVolume *                  volume,
       itk::DRRTransferFunction * transfer,
       GeometryType *             geometry,
       const Settings &           settings,
       bool                       zeroAttenuation)
{
  using PointBasedType = itk::PointBasedDRRImageFilter<TVolume, TProjection>;
  auto drr = PointBasedType::New();
  drr->SetInput(volume);
  drr->SetGeometry(geometry);
  drr->SetTransferFunction(transfer);
  drr->SetTransform(settings.Transform);
  drr->SetSampler(itk::DRRSamplerFactory::GetEntries()[settings.Sampler].Create());
  drr->SetReconstructionKernel(settings.Kernel);
  drr->SetSplat(settings.Splat);
  drr->SetPointWeighting(settings.Weighting);
  drr->SetNumberOfStrata(settings.Strata);
  drr->SetSeed(settings.Seed);
  drr->SetNumberOfSamples(settings.Samples);
  drr->SetOutputMode(settings.OutputMode);
  drr->SetWindowLevel(settings.WindowLevel);
  drr->SetWindowWidth(settings.WindowWidth);
  drr->SetReusePoints(settings.Reuse);
  UseThreads(drr.GetPointer(), settings.Threads);
  if (Accepted([&] { drr->Update(); }, "PointBasedDRRImageFilter::Update()", reader))
  {
    if (!std::isfinite(drr->GetTotalMass()) || !(drr->GetTotalMass() >= 0.0))
    {
      Finding("PointBasedDRRImageFilter: the total mass " + std::to_string(drr->GetTotalMass()) +
                " is not finite and non-negative",
              reader);
    }
    CheckOutputs(drr->GetOutput(),
                 drr->GetStandardErrorOutput(),
                 settings.OutputMode,
                 zeroAttenuation,
                 "PointBasedDRRImageFilter",
                 reader);
    if (settings.RefineSamples > 0 &&
        Accepted([&] { drr->Refine(settings.RefineSamples); }, "PointBasedDRRImageFilter::Refine()", reader))
    {
      CheckOutputs(drr->GetOutput(),
                   drr->GetStandardErrorOutput(),
                   settings.OutputMode,
                   zeroAttenuation,
                   "PointBasedDRRImageFilter after Refine()",
                   reader);
    }
    if (settings.Reuse) // a second pose re-projects the kept points
    {
      geometry->SetGantryAngleInDegrees(geometry->GetGantryAngleInDegrees() + settings.SecondPoseGantry);
      if (Accepted([&] { drr->Update(); }, "PointBasedDRRImageFilter::Update() at a second pose", reader))
      {
        CheckOutputs(drr->GetOutput(),
                     drr->GetStandardErrorOutput(),
                     settings.OutputMode,
                     zeroAttenuation,
                     "PointBasedDRRImageFilter at a second pose (reused points)",
                     reader);
      }
    }
  }

  using ExactType = itk::ExactDRRImageFilter<TVolume, TProjection>;
  auto exact = ExactType::New();
  exact->SetInput(volume);
  exact->SetGeometry(geometry);
  exact->SetTransferFunction(transfer);
  exact->SetTransform(settings.Transform);
  exact->SetReconstructionKernel(settings.Kernel);
  exact->SetRaysPerPixelSide(settings.RaysPerPixelSide);
  exact->SetOutputMode(settings.OutputMode);
  exact->SetWindowLevel(settings.WindowLevel);
  exact->SetWindowWidth(settings.WindowWidth);
  UseThreads(exact.GetPointer(), settings.Threads);
  if (Accepted([&] { exact->Update(); }, "ExactDRRImageFilter::Update()", reader))
  {
    CheckOutputs<TProjection>(
      exact->GetOutput(), nullptr, settings.OutputMode, zeroAttenuation, "ExactDRRImageFilter", reader);
  }
}
} // namespace

extern "C" int
LLVMFuzzerInitialize(int *, char ***)
{
  itk::Object::GlobalWarningDisplayOff();
  return 0;
}

extern "C" int
LLVMFuzzerTestOneInput(const uint8_t * data, size_t size)
{
  Reader reader(data, size);
  if (reader.Flag("floatVoxels"))
  {
    RunCase<itk::Image<float, 3>>(reader, true);
  }
  else
  {
    RunCase<itk::Image<short, 3>>(reader, false);
  }
  return 0;
}
