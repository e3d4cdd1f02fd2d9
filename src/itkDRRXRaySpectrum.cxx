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
#include "itkDRRXRaySpectrum.h"

#include "itkDRRMaterialTable.h"
#include "itkDRRNumberParser.h"
#include "itkDRRTextFileReader.h"

#include <cmath>
#include <sstream>

namespace itk
{
namespace
{
// "" if bin i of the spectrum is valid, otherwise why not.
std::string
CheckBin(const std::vector<double> & energies, const std::vector<double> & fluence, size_t i)
{
  std::ostringstream why;
  const double       e = energies[i];
  if (!(e >= DRRMaterialTable::MinimumEnergyInKeV && e <= DRRMaterialTable::MaximumEnergyInKeV))
  {
    why << "energy " << e << " keV is outside " << DRRMaterialTable::MinimumEnergyInKeV << " to "
        << DRRMaterialTable::MaximumEnergyInKeV << " keV";
  }
  else if (i > 0 && !(e > energies[i - 1]))
  {
    why << "energy " << e << " keV is not above the previous bin's " << energies[i - 1]
        << " keV (energies must be strictly increasing: unsorted or duplicate)";
  }
  else if (!std::isfinite(fluence[i]) || fluence[i] < 0.0)
  {
    why << "fluence " << fluence[i] << " at " << e << " keV must be finite and >= 0";
  }
  return why.str();
}
} // namespace

void
DRRXRaySpectrum::SetSpectrum(const std::vector<double> & energiesInKeV, const std::vector<double> & fluence)
{
  if (energiesInKeV.empty() || energiesInKeV.size() != fluence.size())
  {
    itkExceptionMacro("a spectrum needs as many fluences as energies, and at least one: got "
                      << energiesInKeV.size() << " energies and " << fluence.size() << " fluences");
  }
  double total = 0.0;
  for (size_t i = 0; i < energiesInKeV.size(); ++i)
  {
    const std::string why = CheckBin(energiesInKeV, fluence, i);
    if (!why.empty())
    {
      itkExceptionMacro("spectrum bin " << i << ": " << why);
    }
    total += fluence[i];
  }
  if (!(total > 0.0) || !std::isfinite(total))
  {
    itkExceptionMacro("the spectrum has no photons (every fluence is 0) or an infinite total");
  }
  m_Energies = energiesInKeV;
  m_Fluence = fluence;
  this->Modified();
}

void
DRRXRaySpectrum::ReadFile(const std::string & path)
{
  const auto          lines = DRRTextFileReader::Read(path, "spectrum");
  std::vector<double> energies, fluence;
  for (const auto & line : lines)
  {
    const auto & fields = line.second;
    double       values[2] = { 0.0, 0.0 };
    if (fields.size() != 2 || !DRRNumberParser::ParseFiniteNumber(fields[0], values[0]) ||
        !DRRNumberParser::ParseFiniteNumber(fields[1], values[1]))
    {
      itkExceptionMacro("spectrum file '" << path << "', line " << line.first
                                          << ": expected two finite numbers, energy_keV and fluence, got '"
                                          << (fields.empty() ? std::string() : fields[0])
                                          << (fields.size() > 1 ? " " + fields[1] : std::string())
                                          << (fields.size() > 2 ? " ..." : "") << "'");
    }
    energies.push_back(values[0]);
    fluence.push_back(values[1]);
    const std::string why = CheckBin(energies, fluence, energies.size() - 1);
    if (!why.empty())
    {
      itkExceptionMacro("spectrum file '" << path << "', line " << line.first << ": " << why);
    }
  }
  if (energies.empty())
  {
    itkExceptionMacro("spectrum file '" << path << "' has no bin (empty)");
  }
  double total = 0.0;
  for (const double n : fluence)
  {
    total += n;
  }
  if (!(total > 0.0) || !std::isfinite(total))
  {
    itkExceptionMacro("spectrum file '" << path << "' has no photons (every fluence is 0) or an infinite total");
  }
  m_Energies = energies;
  m_Fluence = fluence;
  this->Modified();
}

void
DRRXRaySpectrum::SetKramers(double kVp, double aluminiumFiltrationInMillimetres, double binWidthInKeV)
{
  if (!(kVp > DRRMaterialTable::MinimumEnergyInKeV && kVp <= DRRMaterialTable::MaximumEnergyInKeV))
  {
    itkExceptionMacro("Kramers spectrum: kVp must be in (" << DRRMaterialTable::MinimumEnergyInKeV << ", "
                                                           << DRRMaterialTable::MaximumEnergyInKeV << "] kV, got "
                                                           << kVp);
  }
  if (!(aluminiumFiltrationInMillimetres >= 0.0) || !std::isfinite(aluminiumFiltrationInMillimetres))
  {
    itkExceptionMacro("Kramers spectrum: the aluminium filtration must be finite and >= 0 mm, got "
                      << aluminiumFiltrationInMillimetres);
  }
  if (!(binWidthInKeV > 0.0 && binWidthInKeV <= 0.5 * kVp))
  {
    itkExceptionMacro("Kramers spectrum: the bin width must be in (0, kVp / 2] keV, got " << binWidthInKeV);
  }
  std::vector<double> energies, fluence;
  for (size_t k = 0;; ++k)
  {
    const double e = (static_cast<double>(k) + 0.5) * binWidthInKeV;
    if (!(e < kVp))
    {
      break;
    }
    if (e < DRRMaterialTable::MinimumEnergyInKeV)
    {
      continue;
    }
    const double muAl =
      DRRMaterialTable::MassAttenuationInCm2PerGram("Al", e) * AluminiumDensityInGramsPerCubicCentimetre / 10.0; // 1/mm
    energies.push_back(e);
    fluence.push_back((kVp - e) / e * std::exp(-muAl * aluminiumFiltrationInMillimetres));
  }
  this->SetSpectrum(energies, fluence); // throws if the filter leaves no photon
}

double
DRRXRaySpectrum::GetMeanEnergyInKeV() const
{
  if (m_Energies.empty())
  {
    itkExceptionMacro("no spectrum is set");
  }
  double sum = 0.0, weighted = 0.0;
  for (size_t i = 0; i < m_Energies.size(); ++i)
  {
    sum += m_Fluence[i];
    weighted += m_Fluence[i] * m_Energies[i];
  }
  return weighted / sum;
}

void
DRRXRaySpectrum::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfBins: " << m_Energies.size() << std::endl;
  if (!m_Energies.empty())
  {
    os << indent << "Energies (keV): " << m_Energies.front() << " to " << m_Energies.back() << std::endl;
    os << indent << "MeanEnergyInKeV: " << this->GetMeanEnergyInKeV() << std::endl;
  }
}
} // namespace itk
