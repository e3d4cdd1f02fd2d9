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
#include "pbdrrDicomLocalizerGeometry.h"
#include "pbdrrDicomValues.h"

#include "gdcmAttribute.h"
#include "gdcmReader.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace pbdrr
{
namespace
{
using VectorType = itk::DRRProjectionGeometry::VectorType;

std::vector<double>
RequiredNumbers(const gdcm::DataSet & dataSet,
                uint16_t              group,
                uint16_t              element,
                size_t                count,
                const std::string &   name,
                const std::string &   path)
{
  std::string         text;
  std::vector<double> numbers;
  if (!StringValue(dataSet, gdcm::Tag(group, element), text) || !ParseNumbers(text.c_str(), count, numbers) ||
      !std::all_of(numbers.begin(), numbers.end(), [](double v) { return std::isfinite(v); }))
  {
    std::ostringstream message;
    message << path << ": the localizer's " << name << " (" << std::hex << std::setfill('0') << std::setw(4) << group
            << "," << std::setw(4) << element << ") is missing or not " << std::dec << count << " number(s)";
    throw std::runtime_error(message.str());
  }
  return numbers;
}

VectorType
UnitVector(const std::vector<double> & numbers, size_t first, const std::string & path)
{
  VectorType v;
  for (unsigned int a = 0; a < 3; ++a)
  {
    v[a] = numbers[first + a];
  }
  const double norm = v.GetNorm();
  if (!(norm > 0.5 && norm < 2.0))
  {
    throw std::runtime_error(path + ": the localizer's Image Orientation (0020,0037) is not two unit vectors");
  }
  return v / norm;
}
} // namespace

LocalizerView
ReadLocalizerView(const std::string & path)
{
  gdcm::Reader reader;
  reader.SetFileName(path.c_str());
  if (!reader.ReadUpToTag(gdcm::Tag(0x7fe0, 0x0010)))
  {
    throw std::runtime_error(path + ": not a DICOM file GDCM reads (--geometry-from takes a CT localizer's file)");
  }
  const gdcm::DataSet & dataSet = reader.GetFile().GetDataSet();
  std::string           imageType;
  StringValue(dataSet, gdcm::Tag(0x0008, 0x0008), imageType);
  std::string upper = imageType;
  std::transform(upper.begin(), upper.end(), upper.begin(), [](unsigned char c) { return std::toupper(c); });
  if (upper.find("LOCALIZER") == std::string::npos)
  {
    imageType.erase(imageType.find_last_not_of(" \0", std::string::npos, 2) + 1);
    throw std::runtime_error(path + ": not a CT localizer (Image Type (0008,0008) is '" + imageType +
                             "', without LOCALIZER): --geometry-from takes a localizer's file");
  }
  gdcm::Attribute<0x0028, 0x0010> rowsAttribute{};
  gdcm::Attribute<0x0028, 0x0011> columnsAttribute{};
  if (!dataSet.FindDataElement(rowsAttribute.GetTag()) || !dataSet.FindDataElement(columnsAttribute.GetTag()))
  {
    throw std::runtime_error(path + ": the localizer has no Rows (0028,0010) or Columns (0028,0011)");
  }
  rowsAttribute.SetFromDataSet(dataSet);
  columnsAttribute.SetFromDataSet(dataSet);
  const std::vector<double> rows{ static_cast<double>(rowsAttribute.GetValue()) };
  const std::vector<double> columns{ static_cast<double>(columnsAttribute.GetValue()) };
  const auto                spacing = RequiredNumbers(dataSet, 0x0028, 0x0030, 2, "Pixel Spacing", path);
  const auto                position = RequiredNumbers(dataSet, 0x0020, 0x0032, 3, "Image Position (Patient)", path);
  const auto   orientation = RequiredNumbers(dataSet, 0x0020, 0x0037, 6, "Image Orientation (Patient)", path);
  const double sid = RequiredNumbers(dataSet, 0x0018, 0x1110, 1, "Distance Source to Detector", path)[0];
  const double sad = RequiredNumbers(dataSet, 0x0018, 0x1111, 1, "Distance Source to Patient", path)[0];
  if (!(rows[0] >= 1.0 && columns[0] >= 1.0 && spacing[0] > 0.0 && spacing[1] > 0.0))
  {
    throw std::runtime_error(path + ": the localizer's size or pixel spacing is not positive");
  }
  if (!(sad > 0.0 && sid > sad))
  {
    std::ostringstream message;
    message << path
            << ": the localizer's distances are not a source, a patient and a detector in that order (source to "
            << "patient " << sad << " mm, source to detector " << sid << " mm)";
    throw std::runtime_error(message.str());
  }
  const VectorType alongColumns = UnitVector(orientation, 0, path); // increasing column index
  const VectorType alongRows = UnitVector(orientation, 3, path);    // increasing row index
  if (std::abs(alongColumns * alongRows) > 1e-3)
  {
    throw std::runtime_error(path + ": the localizer's Image Orientation (0020,0037) is not orthogonal");
  }
  // The table moves along the patient's z axis: it must be the rows' direction (parallel rays along the rows).
  if (std::abs(alongRows[2]) < 1.0 - 1e-3)
  {
    throw std::runtime_error(path + ": the localizer's rows do not run along the table (patient z): " +
                             (std::abs(alongColumns[2]) >= 1.0 - 1e-3
                                ? std::string("a localizer stored with the table along its columns")
                                : std::string("its image plane is oblique to the table")) +
                             " is not supported; transpose it, or give its view with --geometry");
  }
  const double rowPitch = spacing[0], columnPitch = spacing[1];
  const auto   size = itk::DRRProjectionGeometry::DetectorSizeType{ { static_cast<itk::SizeValueType>(columns[0]),
                                                                      static_cast<itk::SizeValueType>(rows[0]) } };
  itk::DRRProjectionGeometry::PointType isocenter;
  for (unsigned int a = 0; a < 3; ++a)
  {
    isocenter[a] = position[a] + alongColumns[a] * columnPitch * 0.5 * (columns[0] - 1.0) +
                   alongRows[a] * rowPitch * 0.5 * (rows[0] - 1.0);
  }
  auto geometry = itk::DRRProjectionGeometry::New();
  geometry->SetProjection(itk::PointBasedDRREnums::Projection::Localizer);
  geometry->SetSourceToIsocenterDistance(sad);
  geometry->SetSourceToDetectorDistance(sid);
  geometry->SetNormal(itk::CrossProduct(alongRows, alongColumns));
  geometry->SetViewUp(-alongRows);
  geometry->SetIsocenter(isocenter);
  geometry->SetDetectorSize(size);
  itk::DRRProjectionGeometry::DetectorVectorType detectorSpacing;
  detectorSpacing[0] = columnPitch * sid / sad;
  detectorSpacing[1] = rowPitch;
  geometry->SetDetectorSpacing(detectorSpacing);
  geometry->VerifyGeometry();

  const auto         source = geometry->GetSourcePosition();
  std::ostringstream description;
  description << "localizer " << size[0] << " x " << size[1] << " at " << columnPitch << " x " << rowPitch
              << " mm (isocenter plane), source to patient " << sad << " mm, to detector " << sid << " mm, source at ("
              << source[0] << ", " << source[1] << ", " << source[2] << ")";
  return { geometry, description.str() };
}
} // namespace pbdrr
