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
#ifndef itkDRRMaterialTable_h
#define itkDRRMaterialTable_h

#include "itkDRRCompatibility.h"
#include "itkObject.h"
#include "itkObjectFactory.h"
#include "PointBasedDRRExport.h"

#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace itk
{
/** \class DRRMaterialTable
 * \brief Maps a CT value (HU) to a material and a mass density (g/cm^3), and a material to its mass attenuation
 * (cm^2/g) at any photon energy (keV) with xraylib.
 *
 * The table is a list of rows, each an HU interval [LowerHU, UpperHU), a material and the density (g/cm^3) at the
 * interval's two ends, linear in HU in between. The rows are contiguous and sorted (each row starts where the one
 * before ends) and, to be used, cover every HU: the first row starts at -inf and the last ends at +inf (IsComplete()).
 * A row with an infinite bound has a constant density (the density clamped at its finite end): its two densities
 * must be equal. Several rows may name the same material: materials are numbered 0, 1, ... in the order of their
 * first row, and a channel of the polychromatic renderer is a material, not a row.
 *
 * A material is a name xraylib knows: a NIST compound (GetCompoundDataNISTList(), e.g. "Water, Liquid", "Air, Dry
 * (near sea level)", "Tissue, Soft (ICRP)", "Bone, Cortical (ICRP)", "Adipose Tissue (ICRP)", "Lung (ICRP)") or a
 * chemical formula ("H2O", "Al", "Ca5(PO4)3OH"). Its mass attenuation is xraylib's CS_Total_CP (total, with coherent
 * scattering: NIST XCOM's "total attenuation with coherent scattering"), from MinimumEnergyInKeV to
 * MaximumEnergyInKeV.
 *
 * SetDefault() loads the three-material table of DeepDRR (Unberath et al., "DeepDRR: a catalyst for machine learning
 * in fluoroscopy-guided procedures", MICCAI 2018; repository arcadelab/deepdrr, deepdrr/load_dicom.py:
 * conv_hu_to_materials_thresholding and conv_hu_to_density): air below -800 HU, soft tissue from -800 to 350 HU, bone
 * above, with DeepDRR's density max(0, min(1.030 + 0.001029 HU, 1.030 + 0.0005886 HU)) g/cm^3 (two straight lines
 * fitted to Schneider et al.'s HU-density data, meeting at 0 HU). Here: the intervals are [low, high) where DeepDRR's
 * are (low, high] (only the integer values -800 and 350 HU differ), the density is held at 0.001 g/cm^3 below
 * -1000 HU (DeepDRR's value at -1000 HU; DeepDRR reaches 0 at -1001 HU, which would make scanner padding vacuum) and
 * at 2.7958 g/cm^3 above 3000 HU (DeepDRR's line at 3000 HU, the end of the data it was fitted to). The materials
 * are the NIST compounds "Air, Dry (near sea level)", "Tissue, Soft (ICRP)" and "Bone, Cortical (ICRP)". Soft tissue
 * of 0 HU then has 1.030 g/cm^3, and mu 1.6 % above water's at 60 keV. ReadFile() replaces the table.
 *
 * File format (ReadFile()): one row a line, five fields separated by whitespace or commas: lower HU, upper HU,
 * material, density at the lower HU (g/cm^3), density at the upper HU (g/cm^3). A material name with spaces or commas
 * is written in double quotes. "-inf" / "inf" are the open ends. '#' starts a comment. Example:
 * \code
 * # lower_HU  upper_HU  material                      density_lower  density_upper  (g/cm^3)
 * -inf        -1000     "Air, Dry (near sea level)"   0.001          0.001
 * -1000       -800      "Air, Dry (near sea level)"   0.001          0.2068
 * -800        350       "Tissue, Soft (ICRP)"         0.2068         1.236
 * 350         inf       "Bone, Cortical (ICRP)"       1.236          1.236
 * \endcode
 *
 * Thread safety: the lookups and GetMassAttenuation() may be called from several threads at once (the mass
 * attenuations are cached behind a mutex); changing the table may not overlap them.
 *
 * \sa DRRTransferFunction::SetMaterialTable(), DRRPolychromaticImageFilter, DRRXRaySpectrum
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRMaterialTable : public Object
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRMaterialTable);

  /** Standard class type aliases. */
  using Self = DRRMaterialTable;
  using Superclass = Object;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  /** \brief One row: an HU interval, its material and its densities. */
  struct RowType
  {
    /** Lower bound of the interval, HU (included; may be -inf for the first row). */
    double LowerHU;
    /** Upper bound of the interval, HU (excluded; may be +inf for the last row). */
    double UpperHU;
    /** Index of the row's material (GetMaterialName()). */
    unsigned int Material;
    /** Density at LowerHU, g/cm^3. */
    double DensityAtLowerInGramsPerCubicCentimetre;
    /** Density at UpperHU, g/cm^3. */
    double DensityAtUpperInGramsPerCubicCentimetre;
  };

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(DRRMaterialTable);

  /** Lowest photon energy of the mass attenuations, keV (xraylib 4.0 tabulates from 0.1 keV; 1 keV is below any
   * diagnostic beam). */
  static constexpr double MinimumEnergyInKeV = 1.0;
  /** Highest photon energy of the mass attenuations, keV (xraylib 4.0's cross sections end a little above 800 keV
   * for every element). */
  static constexpr double MaximumEnergyInKeV = 800.0;

  /** Appends a row: HU interval [lowerHU, upperHU), the material (a name xraylib knows), and the densities (g/cm^3,
   * finite, >= 0) at its two ends. Throws if lowerHU is not the previous row's upperHU (the first row may start
   * anywhere, -inf included), if upperHU <= lowerHU, if an infinite end has a density different from the other end's,
   * or if xraylib does not know the material (the message names it). */
  void
  AddMaterial(double              lowerHU,
              double              upperHU,
              const std::string & material,
              double              densityAtLowerInGramsPerCubicCentimetre,
              double              densityAtUpperInGramsPerCubicCentimetre);

  /** Removes every row and material. */
  void
  Clear();

  /** Replaces the table by DeepDRR's three materials (the class description). */
  void
  SetDefault();

  /** Replaces the table by the rows of a text file (the class description's format). Throws, naming the file and
   * the line, if the file cannot be read, a line has not five fields, a number is not one (NaN included), rows are
   * unsorted, overlap or leave a gap, a density is negative, a material is unknown, or the rows do not cover every HU;
   * the table is unchanged then. */
  void
  ReadFile(const std::string & path);

  /** Number of distinct materials. */
  unsigned int
  GetNumberOfMaterials() const
  {
    return static_cast<unsigned int>(m_MaterialNames.size());
  }
  /** Number of rows. */
  unsigned int
  GetNumberOfRows() const
  {
    return static_cast<unsigned int>(m_Rows.size());
  }
  /** Row i (0 <= i < GetNumberOfRows(); throws otherwise). */
  const RowType &
  GetRow(unsigned int i) const;
  /** Name of material i as given (0 <= i < GetNumberOfMaterials(); throws otherwise). */
  const std::string &
  GetMaterialName(unsigned int material) const;
  /** True if the rows cover every HU (the first starts at -inf, the last ends at +inf). */
  bool
  IsComplete() const;

  /** Index of the material of a CT value (HU). Throws for NaN or a value no row covers. */
  unsigned int
  GetMaterialIndex(double hu) const;
  /** Density of a CT value, g/cm^3 (linear in HU inside its row). Throws as GetMaterialIndex(). */
  double
  GetDensity(double hu) const;
  /** Mass attenuation of a material at a photon energy, cm^2/g (xraylib CS_Total_CP, cached). Throws for a material
   * index out of range or an energy outside [MinimumEnergyInKeV, MaximumEnergyInKeV]. */
  double
  GetMassAttenuation(unsigned int material, double energyInKeV) const;
  /** Linear attenuation of a CT value at a photon energy, 1/mm: density (g/cm^3) x mass attenuation (cm^2/g) / 10. */
  double
  GetMuPerMillimeter(double hu, double energyInKeV) const;

  /** Mass attenuation (cm^2/g) of any material name xraylib knows, at a photon energy (keV): xraylib's CS_Total_CP.
   * Throws, naming the material, for an unknown name or an energy outside [MinimumEnergyInKeV, MaximumEnergyInKeV]. */
  static double
  MassAttenuationInCm2PerGram(const std::string & material, double energyInKeV);

protected:
  DRRMaterialTable() = default;
  ~DRRMaterialTable() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  const RowType &
  FindRow(double hu) const;

  std::vector<RowType>     m_Rows;
  std::vector<std::string> m_MaterialNames;
  // (material, energy in keV) -> cm^2/g; filled on demand by GetMassAttenuation().
  mutable std::map<std::pair<unsigned int, double>, double> m_MassAttenuationCache;
  mutable std::mutex                                        m_CacheMutex;
};
} // namespace itk

#endif
