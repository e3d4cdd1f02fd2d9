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
#ifndef itkDRRXRaySpectrum_h
#define itkDRRXRaySpectrum_h

#include "itkDRRCompatibility.h"
#include "itkObject.h"
#include "itkObjectFactory.h"
#include "PointBasedDRRExport.h"

#include <string>
#include <vector>

namespace itk
{
/** \class DRRXRaySpectrum
 * \brief A discrete X-ray spectrum: photon energies (keV) and the fluence of each (photons per bin, any scale).
 *
 * Energies are strictly increasing, in [DRRMaterialTable::MinimumEnergyInKeV, DRRMaterialTable::MaximumEnergyInKeV]
 * (1 to 800 keV, where xraylib has cross sections); fluences are finite, >= 0 and not all 0. Only the shape of the
 * fluence matters to DRRPolychromaticImageFilter (it divides by the sum).
 *
 * Three ways to set it:
 * - SetSpectrum(energies, fluence).
 * - ReadFile(): two columns, energy (keV) and fluence, separated by whitespace or a comma; '#' starts a comment.
 *   A SpekPy or TASMICS spectrum exported as text reads as it is. Example:
 *   \code
 *   # energy_keV  fluence
 *   20.5  1.2e3
 *   21.5  2.4e3
 *   \endcode
 * - SetKramers(kVp, aluminium, binWidth): Kramers' law for the bremsstrahlung of a thick target, photon fluence
 *   N(E) dE proportional to (kVp - E) / E dE (H. A. Kramers, "On the theory of X-ray absorption and of the continuous
 *   X-ray spectrum", Phil. Mag. 46, 836-871 (1923)), hardened by an aluminium filter: times exp(-(mu/rho)_Al(E)
 *   rho_Al t / 10), (mu/rho)_Al from xraylib (cm^2/g), rho_Al = 2.699 g/cm^3, t in mm. Bins of width w, centred at
 *   (k + 0.5) w below kVp, each given the fluence at its centre (midpoint rule); bins centred below 1 keV are left
 *   out (the unfiltered law diverges as 1/E there; 2.5 mm of aluminium transmits nothing below 10 keV anyway).
 *   Limits: no characteristic lines (tungsten's K lines, 58.0, 59.3 and 67.2 keV, appear above its K edge, 69.5 keV:
 *   at 120 kVp they carry several percent of the photons, close to the mean energy, which moves little), no anode
 *   self-filtration (heel effect), no inherent filtration of the tube window besides the aluminium given, and
 *   Kramers' law itself is a thin-shell approximation (it overestimates the lowest energies, which the filter
 *   removes). For measured or accurately modelled spectra read a SpekPy or TASMICS file.
 *
 * \sa DRRPolychromaticImageFilter, DRRMaterialTable
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRXRaySpectrum : public Object
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRXRaySpectrum);

  /** Standard class type aliases. */
  using Self = DRRXRaySpectrum;
  using Superclass = Object;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(DRRXRaySpectrum);

  /** Density of the aluminium filter of SetKramers(), g/cm^3. */
  static constexpr double AluminiumDensityInGramsPerCubicCentimetre = 2.699;

  /** Sets the spectrum: energies (keV) and fluences (photons per bin), of equal, nonzero length. Throws (naming the
   * bin) for energies not strictly increasing or outside 1 to 800 keV, a negative or non-finite fluence, or all
   * fluences 0; the spectrum is unchanged then. */
  void
  SetSpectrum(const std::vector<double> & energiesInKeV, const std::vector<double> & fluence);

  /** Reads a two-column text file (the class description). Throws, naming the file and the line, for a missing file,
   * a line without two numbers, NaN, a negative fluence, unsorted or duplicate energies, an energy out of range, or a
   * file without a bin or without photons. */
  void
  ReadFile(const std::string & path);

  /** Kramers' thick-target spectrum at the tube voltage kVp (kV; photon energies up to kVp keV, in (1, 800]),
   * filtered by aluminiumFiltrationInMillimetres (>= 0, mm) of aluminium, in bins of binWidthInKeV (keV, > 0, at most
   * kVp / 2): see the class description. */
  void
  SetKramers(double kVp, double aluminiumFiltrationInMillimetres = 2.5, double binWidthInKeV = 1.0);

  /** The bins' photon energies, keV. */
  const std::vector<double> &
  GetEnergies() const
  {
    return m_Energies;
  }
  /** The bins' fluences, photons per bin. */
  const std::vector<double> &
  GetFluence() const
  {
    return m_Fluence;
  }
  /** Number of bins (0 before the spectrum is set). */
  unsigned int
  GetNumberOfBins() const
  {
    return static_cast<unsigned int>(m_Energies.size());
  }
  /** Fluence-weighted mean photon energy, keV (sum E N(E) / sum N(E)); throws if no spectrum is set. */
  double
  GetMeanEnergyInKeV() const;

protected:
  DRRXRaySpectrum() = default;
  ~DRRXRaySpectrum() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  std::vector<double> m_Energies;
  std::vector<double> m_Fluence;
};
} // namespace itk

#endif
