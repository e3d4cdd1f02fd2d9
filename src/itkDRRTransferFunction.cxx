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
#include "itkDRRTransferFunction.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace itk
{
namespace
{
struct WaterAttenuationEntry
{
  double energyInKeV;
  double massAttenuationInCm2PerGram; // mu / rho, liquid water, NIST XCOM (with coherent scattering)
};

// NIST X-ray mass attenuation coefficients, water (liquid), density 1 g/cm^3.
constexpr std::array<WaterAttenuationEntry, 17> waterTable = { { { 10.0, 5.329 },
                                                                 { 15.0, 1.673 },
                                                                 { 20.0, 0.8096 },
                                                                 { 30.0, 0.3756 },
                                                                 { 40.0, 0.2683 },
                                                                 { 50.0, 0.2269 },
                                                                 { 60.0, 0.2059 },
                                                                 { 80.0, 0.1837 },
                                                                 { 100.0, 0.1707 },
                                                                 { 150.0, 0.1505 },
                                                                 { 200.0, 0.1370 },
                                                                 { 300.0, 0.1186 },
                                                                 { 400.0, 0.1061 },
                                                                 { 500.0, 0.09687 },
                                                                 { 600.0, 0.08956 },
                                                                 { 800.0, 0.07865 },
                                                                 { 1000.0, 0.07072 } } };
} // namespace

double
DRRTransferFunction::WaterAttenuationPerMillimeter(double energyInKeV)
{
  if (!(energyInKeV >= waterTable.front().energyInKeV && energyInKeV <= waterTable.back().energyInKeV))
  {
    itkGenericExceptionMacro("DRRTransferFunction: effective energy "
                             << energyInKeV << " keV is outside the NIST water table ("
                             << waterTable.front().energyInKeV << " to " << waterTable.back().energyInKeV << " keV)");
  }
  auto upper = std::lower_bound(waterTable.begin(),
                                waterTable.end(),
                                energyInKeV,
                                [](const WaterAttenuationEntry & entry, double e) { return entry.energyInKeV < e; });
  if (upper->energyInKeV == energyInKeV)
  {
    return upper->massAttenuationInCm2PerGram / 10.0; // 1/cm -> 1/mm at 1 g/cm^3
  }
  const auto   lower = upper - 1;
  const double t = std::log(energyInKeV / lower->energyInKeV) / std::log(upper->energyInKeV / lower->energyInKeV);
  const double logMu =
    (1.0 - t) * std::log(lower->massAttenuationInCm2PerGram) + t * std::log(upper->massAttenuationInCm2PerGram);
  return std::exp(logMu) / 10.0;
}

void
DRRTransferFunction::SetEffectiveEnergyInKeV(double energyInKeV)
{
  const double muWater = WaterAttenuationPerMillimeter(energyInKeV); // throws outside 10 .. 1000 keV
  if (m_Mode == ModeEnum::Materials && m_MaterialTable && energyInKeV > DRRMaterialTable::MaximumEnergyInKeV)
  {
    itkExceptionMacro("the Materials transfer function needs an effective energy of at most "
                      << DRRMaterialTable::MaximumEnergyInKeV << " keV (xraylib's range), got " << energyInKeV
                      << " keV");
  }
  m_MuWaterPerMillimeter = muWater;
  m_EffectiveEnergyInKeV = energyInKeV;
  if (m_MaterialTable && energyInKeV <= DRRMaterialTable::MaximumEnergyInKeV)
  {
    this->UpdateMaterialCache();
  }
  this->Modified();
}

void
DRRTransferFunction::SetMaterialTable(DRRMaterialTable * table)
{
  if (table == nullptr)
  {
    itkExceptionMacro("the Materials transfer function needs a material table, got none");
  }
  if (!table->IsComplete())
  {
    itkExceptionMacro("the material table must cover every HU (rows from -inf to inf); it has "
                      << table->GetNumberOfRows() << " rows");
  }
  m_MaterialTable = table;
  m_Mode = ModeEnum::Materials;
  if (m_EffectiveEnergyInKeV > 0.0 && m_EffectiveEnergyInKeV <= DRRMaterialTable::MaximumEnergyInKeV)
  {
    this->UpdateMaterialCache();
  }
  this->Modified();
}

void
DRRTransferFunction::UpdateMaterialCache()
{
  std::vector<double> cache(m_MaterialTable->GetNumberOfMaterials());
  for (unsigned int m = 0; m < cache.size(); ++m)
  {
    cache[m] = m_MaterialTable->GetMassAttenuation(m, m_EffectiveEnergyInKeV);
  }
  m_MassAttenuationAtReference = cache;
  m_MaterialCacheTime = m_MaterialTable->GetMTime();
  m_MaterialCacheEnergyInKeV = m_EffectiveEnergyInKeV;
}

double
DRRTransferFunction::EvaluateMaterials(double inputValue) const
{
  if (!m_MaterialTable)
  {
    itkExceptionMacro("the Materials transfer function has no material table (SetMaterialTable())");
  }
  if (!(m_EffectiveEnergyInKeV > 0.0))
  {
    itkExceptionMacro("the Materials transfer function needs an effective energy (SetEffectiveEnergyInKeV()), not "
                      "mu_water alone");
  }
  if (m_MaterialCacheTime == m_MaterialTable->GetMTime() && m_MaterialCacheEnergyInKeV == m_EffectiveEnergyInKeV)
  {
    const unsigned int material = m_MaterialTable->GetMaterialIndex(inputValue);
    return m_MaterialTable->GetDensity(inputValue) * m_MassAttenuationAtReference[material] / 10.0;
  }
  return m_MaterialTable->GetMuPerMillimeter(inputValue, m_EffectiveEnergyInKeV); // the table changed since
}

int
DRRTransferFunction::GetMaterialIndex(double inputValue) const
{
  if (m_Mode != ModeEnum::Materials)
  {
    return -1;
  }
  if (!m_MaterialTable)
  {
    itkExceptionMacro("the Materials transfer function has no material table (SetMaterialTable())");
  }
  return static_cast<int>(m_MaterialTable->GetMaterialIndex(inputValue));
}

void
DRRTransferFunction::SetMuWaterPerMillimeter(double muWater)
{
  // Water attenuates between about 0.005 /mm (10 MeV) and 0.53 /mm (10 keV): anything far outside is a unit error.
  if (!(muWater > 0.0) || !(muWater <= 10.0))
  {
    itkExceptionMacro("mu_water must be positive and at most 10 /mm (water is 0.02059 /mm at 60 keV), got " << muWater
                                                                                                            << " /mm");
  }
  m_MuWaterPerMillimeter = muWater;
  m_EffectiveEnergyInKeV = 0.0; // no longer derived from an energy
  this->Modified();
}

void
DRRTransferFunction::SetPiecewiseLinearPoints(const PointListType & points)
{
  if (points.empty())
  {
    itkExceptionMacro("the piecewise-linear transfer function needs at least one (value, mu) point");
  }
  for (size_t i = 0; i < points.size(); ++i)
  {
    if (!std::isfinite(points[i].first) || !std::isfinite(points[i].second) || points[i].second < 0.0)
    {
      itkExceptionMacro("piecewise-linear point " << i << " (" << points[i].first << ", " << points[i].second
                                                  << "): values must be finite and mu >= 0 /mm");
    }
    if (i > 0 && !(points[i].first > points[i - 1].first))
    {
      itkExceptionMacro("piecewise-linear points must have strictly increasing input values (point " << i << ")");
    }
  }
  m_PiecewiseLinearPoints = points;
  m_Mode = ModeEnum::PiecewiseLinear;
  this->Modified();
}

void
DRRTransferFunction::AddPiecewiseLinearPoint(double inputValue, double muPerMillimeter)
{
  PointListType points = m_PiecewiseLinearPoints;
  points.emplace_back(inputValue, muPerMillimeter);
  this->SetPiecewiseLinearPoints(points); // checks the new point against the last one
}

void
DRRTransferFunction::ClearPiecewiseLinearPoints()
{
  if (!m_PiecewiseLinearPoints.empty())
  {
    m_PiecewiseLinearPoints.clear();
    this->Modified();
  }
}

double
DRRTransferFunction::EvaluatePiecewiseLinear(double inputValue) const
{
  const PointListType & p = m_PiecewiseLinearPoints;
  if (p.empty())
  {
    itkExceptionMacro("the piecewise-linear transfer function has no points");
  }
  if (inputValue <= p.front().first)
  {
    return p.front().second;
  }
  if (inputValue >= p.back().first)
  {
    return p.back().second;
  }
  auto upper = std::upper_bound(
    p.begin(), p.end(), inputValue, [](double v, const std::pair<double, double> & point) { return v < point.first; });
  const auto   lower = upper - 1;
  const double t = (inputValue - lower->first) / (upper->first - lower->first);
  return (1.0 - t) * lower->second + t * upper->second;
}

void
DRRTransferFunction::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "Mode: " << m_Mode << std::endl;
  os << indent << "EffectiveEnergyInKeV: " << m_EffectiveEnergyInKeV << std::endl;
  os << indent << "MuWaterPerMillimeter (1/mm): " << m_MuWaterPerMillimeter << std::endl;
  os << indent << "PiecewiseLinearPoints: " << m_PiecewiseLinearPoints.size() << std::endl;
  os << indent << "AirThreshold (input units): " << m_AirThreshold << std::endl;
  os << indent << "MaterialTable: " << (m_MaterialTable ? "" : "(none)") << std::endl;
  if (m_MaterialTable)
  {
    m_MaterialTable->Print(os, indent.GetNextIndent());
  }
}
} // namespace itk
