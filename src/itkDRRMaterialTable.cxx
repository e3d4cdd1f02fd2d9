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
#include "itkDRRMaterialTable.h"

#include "itkDRRNumberParser.h"
#include "itkDRRTextFileReader.h"

#include <xraylib.h>

#include <cmath>
#include <limits>
#include <sstream>

namespace itk
{
namespace
{
// "inf", "+inf", "-inf" (any case) or a finite number; false otherwise (NaN included).
bool
ParseBound(const std::string & text, double & value)
{
  std::string lower;
  for (const char c : text)
  {
    lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  if (lower == "inf" || lower == "+inf" || lower == "infinity" || lower == "+infinity")
  {
    value = std::numeric_limits<double>::infinity();
    return true;
  }
  if (lower == "-inf" || lower == "-infinity")
  {
    value = -std::numeric_limits<double>::infinity();
    return true;
  }
  return DRRNumberParser::ParseFiniteNumber(text, value);
}

// An exception's description without ITK's "ITK ERROR: Class(0x...): " prefix, to be quoted in another message.
std::string
WithoutPrefix(const ExceptionObject & e)
{
  std::string       text = e.GetDescription();
  const std::string error = "ITK ERROR: ";
  if (text.compare(0, error.size(), error) == 0)
  {
    text.erase(0, error.size());
    const size_t open = text.find('(');
    const size_t end = text.find("): ");
    if (end != std::string::npos && open < end && text.find(' ') > open) // "Class(0x...): ": one word before it
    {
      text.erase(0, end + 3);
    }
  }
  return text;
}
} // namespace

double
DRRMaterialTable::MassAttenuationInCm2PerGram(const std::string & material, double energyInKeV)
{
  if (!(energyInKeV >= MinimumEnergyInKeV && energyInKeV <= MaximumEnergyInKeV))
  {
    itkGenericExceptionMacro("DRRMaterialTable: photon energy " << energyInKeV << " keV of material '" << material
                                                                << "' is outside " << MinimumEnergyInKeV << " to "
                                                                << MaximumEnergyInKeV << " keV");
  }
  xrl_error *  error = nullptr;
  const double value = CS_Total_CP(material.c_str(), energyInKeV, &error);
  if (error != nullptr)
  {
    const std::string message = error->message != nullptr ? error->message : "unknown error";
    xrl_error_free(error);
    itkGenericExceptionMacro("DRRMaterialTable: xraylib does not know the material '"
                             << material << "' at " << energyInKeV << " keV (" << message
                             << "): give a NIST compound name (e.g. \"Water, Liquid\") or a chemical formula");
  }
  if (!(value > 0.0) || !std::isfinite(value))
  {
    itkGenericExceptionMacro("DRRMaterialTable: xraylib gives the mass attenuation "
                             << value << " cm^2/g for '" << material << "' at " << energyInKeV << " keV");
  }
  return value;
}

void
DRRMaterialTable::AddMaterial(double              lowerHU,
                              double              upperHU,
                              const std::string & material,
                              double              densityAtLowerInGramsPerCubicCentimetre,
                              double              densityAtUpperInGramsPerCubicCentimetre)
{
  const double dLow = densityAtLowerInGramsPerCubicCentimetre;
  const double dHigh = densityAtUpperInGramsPerCubicCentimetre;
  if (std::isnan(lowerHU) || std::isnan(upperHU) || lowerHU == std::numeric_limits<double>::infinity() ||
      upperHU == -std::numeric_limits<double>::infinity())
  {
    itkExceptionMacro("material row [" << lowerHU << ", " << upperHU
                                       << ") HU: bounds must be numbers (the lower may be "
                                       << "-inf, the upper +inf)");
  }
  if (!(upperHU > lowerHU))
  {
    itkExceptionMacro("material row [" << lowerHU << ", " << upperHU
                                       << ") HU: the upper bound must be above the lower bound");
  }
  if (!m_Rows.empty() && lowerHU != m_Rows.back().UpperHU)
  {
    itkExceptionMacro("material row [" << lowerHU << ", " << upperHU << ") HU: rows must be sorted and contiguous, "
                                       << (lowerHU < m_Rows.back().UpperHU ? "it overlaps" : "it leaves a gap after")
                                       << " the previous row, which ends at " << m_Rows.back().UpperHU << " HU");
  }
  if (!std::isfinite(dLow) || !std::isfinite(dHigh) || dLow < 0.0 || dHigh < 0.0)
  {
    itkExceptionMacro("material row [" << lowerHU << ", " << upperHU
                                       << ") HU: densities must be finite and >= 0 g/cm^3, "
                                       << "got " << dLow << " and " << dHigh);
  }
  if ((std::isinf(lowerHU) || std::isinf(upperHU)) && dLow != dHigh)
  {
    itkExceptionMacro("material row [" << lowerHU << ", " << upperHU << ") HU: a row with an infinite bound has a "
                                       << "constant density; give the same density at both ends, got " << dLow
                                       << " and " << dHigh << " g/cm^3");
  }
  if (material.empty())
  {
    itkExceptionMacro("material row [" << lowerHU << ", " << upperHU << ") HU: empty material name");
  }
  unsigned int index = 0;
  while (index < m_MaterialNames.size() && m_MaterialNames[index] != material)
  {
    ++index;
  }
  if (index == m_MaterialNames.size())
  {
    MassAttenuationInCm2PerGram(material, 60.0); // throws, naming it, if xraylib does not know it
    m_MaterialNames.push_back(material);
  }
  m_Rows.push_back(RowType{ lowerHU, upperHU, index, dLow, dHigh });
  this->Modified();
}

void
DRRMaterialTable::Clear()
{
  m_Rows.clear();
  m_MaterialNames.clear();
  {
    std::lock_guard<std::mutex> lock(m_CacheMutex);
    m_MassAttenuationCache.clear();
  }
  this->Modified();
}

void
DRRMaterialTable::SetDefault()
{
  // DeepDRR (arcadelab/deepdrr, deepdrr/load_dicom.py): materials by thresholds at -800 and 350 HU, density
  // max(0, min(1.030 + 0.001029 HU, 1.030 + 0.0005886 HU)) g/cm^3; held constant below -1000 and above 3000 HU.
  const auto inf = std::numeric_limits<double>::infinity();
  const auto density = [](double hu) { return std::max(0.0, std::min(1.030 + 0.001029 * hu, 1.030 + 0.0005886 * hu)); };
  const char * air = "Air, Dry (near sea level)";
  const char * soft = "Tissue, Soft (ICRP)";
  const char * bone = "Bone, Cortical (ICRP)";
  this->Clear();
  this->AddMaterial(-inf, -1000.0, air, density(-1000.0), density(-1000.0));
  this->AddMaterial(-1000.0, -800.0, air, density(-1000.0), density(-800.0));
  this->AddMaterial(-800.0, 0.0, soft, density(-800.0), density(0.0));
  this->AddMaterial(0.0, 350.0, soft, density(0.0), density(350.0));
  this->AddMaterial(350.0, 3000.0, bone, density(350.0), density(3000.0));
  this->AddMaterial(3000.0, inf, bone, density(3000.0), density(3000.0));
}

void
DRRMaterialTable::ReadFile(const std::string & path)
{
  const auto lines = DRRTextFileReader::Read(path, "material table");
  auto       table = DRRMaterialTable::New();
  for (const auto & line : lines)
  {
    const auto &       fields = line.second;
    std::ostringstream where;
    where << "material table file '" << path << "', line " << line.first << ": ";
    if (fields.size() != 5)
    {
      itkExceptionMacro(<< where.str() << "expected 5 fields (lower_HU upper_HU material density_lower density_upper), "
                        << "got " << fields.size());
    }
    double       values[4];
    const size_t columns[4] = { 0, 1, 3, 4 };
    const char * names[4] = { "lower HU", "upper HU", "density at the lower HU", "density at the upper HU" };
    for (size_t k = 0; k < 4; ++k)
    {
      const bool parsed = k < 2 ? ParseBound(fields[columns[k]], values[k])
                                : DRRNumberParser::ParseFiniteNumber(fields[columns[k]], values[k]);
      if (!parsed)
      {
        itkExceptionMacro(<< where.str() << "the " << names[k] << " '" << fields[columns[k]] << "' is not a number"
                          << (k < 2 ? " (or -inf / inf)" : " (finite, g/cm^3)"));
      }
    }
    try
    {
      table->AddMaterial(values[0], values[1], fields[2], values[2], values[3]);
    }
    catch (const ExceptionObject & e)
    {
      itkExceptionMacro(<< where.str() << WithoutPrefix(e));
    }
  }
  if (table->m_Rows.empty())
  {
    itkExceptionMacro("material table file '" << path << "' has no row");
  }
  if (!table->IsComplete())
  {
    itkExceptionMacro("material table file '" << path << "', line " << lines.back().first
                                              << ": the rows must cover every HU, from -inf (first row) to inf (last "
                                              << "row); they cover [" << table->m_Rows.front().LowerHU << ", "
                                              << table->m_Rows.back().UpperHU << ")");
  }
  m_Rows = table->m_Rows;
  m_MaterialNames = table->m_MaterialNames;
  {
    std::lock_guard<std::mutex> lock(m_CacheMutex);
    m_MassAttenuationCache.clear();
  }
  this->Modified();
}

const DRRMaterialTable::RowType &
DRRMaterialTable::GetRow(unsigned int i) const
{
  if (i >= m_Rows.size())
  {
    itkExceptionMacro("row " << i << " does not exist (the table has " << m_Rows.size() << " rows)");
  }
  return m_Rows[i];
}

const std::string &
DRRMaterialTable::GetMaterialName(unsigned int material) const
{
  if (material >= m_MaterialNames.size())
  {
    itkExceptionMacro("material " << material << " does not exist (the table has " << m_MaterialNames.size()
                                  << " materials)");
  }
  return m_MaterialNames[material];
}

bool
DRRMaterialTable::IsComplete() const
{
  return !m_Rows.empty() && m_Rows.front().LowerHU == -std::numeric_limits<double>::infinity() &&
         m_Rows.back().UpperHU == std::numeric_limits<double>::infinity();
}

const DRRMaterialTable::RowType &
DRRMaterialTable::FindRow(double hu) const
{
  if (m_Rows.empty() || !(hu >= m_Rows.front().LowerHU && hu < m_Rows.back().UpperHU))
  {
    itkExceptionMacro("CT value " << hu << " HU is not covered by the material table"
                                  << (m_Rows.empty() ? " (it has no row)" : ""));
  }
  // Few rows: a linear search is as fast as a binary one.
  size_t i = 0;
  while (hu >= m_Rows[i].UpperHU)
  {
    ++i;
  }
  return m_Rows[i];
}

unsigned int
DRRMaterialTable::GetMaterialIndex(double hu) const
{
  return this->FindRow(hu).Material;
}

double
DRRMaterialTable::GetDensity(double hu) const
{
  const RowType & row = this->FindRow(hu);
  if (std::isinf(row.LowerHU) || std::isinf(row.UpperHU))
  {
    return row.DensityAtLowerInGramsPerCubicCentimetre; // constant (both ends equal)
  }
  const double t = (hu - row.LowerHU) / (row.UpperHU - row.LowerHU);
  return (1.0 - t) * row.DensityAtLowerInGramsPerCubicCentimetre + t * row.DensityAtUpperInGramsPerCubicCentimetre;
}

double
DRRMaterialTable::GetMassAttenuation(unsigned int material, double energyInKeV) const
{
  const std::string & name = this->GetMaterialName(material);
  const auto          key = std::make_pair(material, energyInKeV);
  {
    std::lock_guard<std::mutex> lock(m_CacheMutex);
    const auto                  found = m_MassAttenuationCache.find(key);
    if (found != m_MassAttenuationCache.end())
    {
      return found->second;
    }
  }
  const double                value = MassAttenuationInCm2PerGram(name, energyInKeV);
  std::lock_guard<std::mutex> lock(m_CacheMutex);
  m_MassAttenuationCache[key] = value;
  return value;
}

double
DRRMaterialTable::GetMuPerMillimeter(double hu, double energyInKeV) const
{
  const RowType & row = this->FindRow(hu);
  return this->GetDensity(hu) * this->GetMassAttenuation(row.Material, energyInKeV) / 10.0; // 1/cm -> 1/mm
}

void
DRRMaterialTable::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "Materials: " << m_MaterialNames.size() << std::endl;
  for (size_t m = 0; m < m_MaterialNames.size(); ++m)
  {
    os << indent.GetNextIndent() << m << ": " << m_MaterialNames[m] << std::endl;
  }
  os << indent << "Rows (HU interval, material, density g/cm^3 at its ends): " << m_Rows.size() << std::endl;
  for (const RowType & row : m_Rows)
  {
    os << indent.GetNextIndent() << "[" << row.LowerHU << ", " << row.UpperHU << ") " << row.Material << " "
       << row.DensityAtLowerInGramsPerCubicCentimetre << " .. " << row.DensityAtUpperInGramsPerCubicCentimetre
       << std::endl;
  }
}
} // namespace itk
