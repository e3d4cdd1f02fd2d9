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
#ifndef itkDRRTransferFunction_h
#define itkDRRTransferFunction_h

#include "itkDRRCompatibility.h"
#include "itkDRRMaterialTable.h"
#include "itkObject.h"
#include "itkObjectFactory.h"
#include "itkPointBasedDRREnums.h"
#include "PointBasedDRRExport.h"

#include <limits>
#include <utility>
#include <vector>

namespace itk
{
/** \class DRRTransferFunction
 * \brief Maps input voxel values (HU for CT, or mu) to linear attenuation mu in 1/mm.
 *
 * - Natural (default): mu = mu_water(E) * max(0, 1 + HU / 1000), HU clamped at -1000 (scanner padding of
 *   -1024, -2048 or -3024 HU becomes air, never negative attenuation). mu_water is interpolated (log-log) from
 *   the NIST XCOM table for liquid water at the effective energy (keV, default 60 keV: 0.02059 /mm), or given
 *   directly with SetMuWaterPerMillimeter().
 * - PiecewiseLinear: user (value, mu) pairs with increasing values, linear in between, constant beyond the ends.
 * - Identity: the input already holds mu in 1/mm.
 * - Materials (SetMaterialTable()): the table's material and density (g/cm^3) of the HU value, mu = density x
 *   (mu/rho)_material(E_ref) / 10 (1/mm), E_ref the effective energy (keV, default 60 keV; xraylib's CS_Total_CP).
 *   GetMaterialIndex() gives the material of a value: the channel a polychromatic render puts the voxel in
 *   (DRRPolychromaticImageFilter).
 *
 * Voxels whose input value is below the air threshold (input units; default: none) get mu = 0 and are never
 * sampled. Every mode maps one input value to one mu, so voxels of one input level share one mu.
 *
 * \sa DRRImageFilterBase::SetTransferFunction(), DRRAttenuationVolume
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRTransferFunction : public Object
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRTransferFunction);

  /** Standard class type aliases. */
  using Self = DRRTransferFunction;
  using Superclass = Object;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;
  /** Natural, PiecewiseLinear, Identity or Materials. */
  using ModeEnum = PointBasedDRREnums::TransferFunction;
  /** (input value, mu in 1/mm) pairs of the piecewise-linear mode. */
  using PointListType = std::vector<std::pair<double, double>>;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(DRRTransferFunction);

  ///@{
  /** The mode: Natural (default), PiecewiseLinear, Identity (input already mu in 1/mm) or Materials (needs a
   * material table: SetMaterialTable()). */
  itkSetEnumMacro(Mode, ModeEnum);
  itkGetConstMacro(Mode, ModeEnum);
  ///@}

  /** Effective photon energy (keV) for the natural transfer function; sets mu_water from the NIST table.
   * Throws outside the table's 10 keV .. 1 MeV. It is also E_ref, the energy of the Materials mode's mu (there it
   * must be at most DRRMaterialTable::MaximumEnergyInKeV, 800 keV). */
  void
  SetEffectiveEnergyInKeV(double energyInKeV);
  /** Effective photon energy, keV (default 60 keV); 0 after SetMuWaterPerMillimeter() (mu_water then derives from no
   * energy). */
  itkGetConstMacro(EffectiveEnergyInKeV, double);

  /** Linear attenuation of water (1/mm) used by the natural transfer function, in (0, 10] 1/mm (throws otherwise);
   * sets the effective energy to 0 (none). */
  void
  SetMuWaterPerMillimeter(double muWater);
  /** Linear attenuation of water, 1/mm (default 0.02059 /mm, water at 60 keV). */
  itkGetConstMacro(MuWaterPerMillimeter, double);

  /** (input value, mu in 1/mm) pairs for the piecewise-linear mode; values strictly increasing, mu >= 0.
   * Also selects the piecewise-linear mode. */
  void
  SetPiecewiseLinearPoints(const PointListType & points);
  /** Appends one (input value, mu in 1/mm) point to the piecewise-linear function, after the last one (its value
   * must be larger), and selects the piecewise-linear mode: the form ITK's Python wrapping can call, point by point. */
  void
  AddPiecewiseLinearPoint(double inputValue, double muPerMillimeter);
  /** Removes every piecewise-linear point (the mode is unchanged; an empty piecewise-linear function throws on use). */
  void
  ClearPiecewiseLinearPoints();
  /** Number of points of the piecewise-linear function. */
  unsigned int
  GetNumberOfPiecewiseLinearPoints() const
  {
    return static_cast<unsigned int>(m_PiecewiseLinearPoints.size());
  }
  /** The (input value, mu in 1/mm) pairs of the piecewise-linear mode. */
  const PointListType &
  GetPiecewiseLinearPoints() const
  {
    return m_PiecewiseLinearPoints;
  }

  /** Selects the Materials mode with this table (HU -> material, density). Throws for a null table or one that does
   * not cover every HU (DRRMaterialTable::IsComplete()). The table is shared, not copied: changing it later changes
   * the transfer function. */
  void
  SetMaterialTable(DRRMaterialTable * table);
  /** The material table of the Materials mode (null if none was set). */
  const DRRMaterialTable *
  GetMaterialTable() const
  {
    return m_MaterialTable.GetPointer();
  }

  /** The material index of an input value (HU) in the Materials mode (DRRMaterialTable::GetMaterialIndex()); -1 in
   * the other modes. Throws for NaN. */
  int
  GetMaterialIndex(double inputValue) const;

  ///@{
  /** Input values strictly below this (input units: HU, or 1/mm for mu input) are air: mu = 0.
   * Default: -infinity (no threshold beyond the model's own zero). */
  itkSetMacro(AirThreshold, double);
  itkGetConstMacro(AirThreshold, double);
  ///@}

  /** mu (1/mm) of one input value. The value must be finite; the result is >= 0 except in Identity mode with
   * negative input, which the filters reject. */
  double
  Evaluate(double inputValue) const
  {
    if (inputValue < m_AirThreshold)
    {
      return 0.0;
    }
    switch (m_Mode)
    {
      case ModeEnum::Natural:
        return inputValue <= -1000.0 ? 0.0 : m_MuWaterPerMillimeter * (1.0 + inputValue / 1000.0);
      case ModeEnum::Identity:
        return inputValue;
      case ModeEnum::PiecewiseLinear:
        return this->EvaluatePiecewiseLinear(inputValue);
      case ModeEnum::Materials:
        return this->EvaluateMaterials(inputValue);
    }
    return 0.0;
  }

  /** Linear attenuation of liquid water (1/mm) at a photon energy (keV), log-log interpolated from NIST XCOM
   * (total attenuation with coherent scattering). Throws outside 10 keV .. 1000 keV. */
  static double
  WaterAttenuationPerMillimeter(double energyInKeV);

protected:
  DRRTransferFunction() = default;
  ~DRRTransferFunction() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  double
  EvaluatePiecewiseLinear(double inputValue) const;
  double
  EvaluateMaterials(double inputValue) const;
  // Recomputes the table's mass attenuations at E_ref (m_MassAttenuationAtReference); throws as xraylib does.
  void
  UpdateMaterialCache();

  ModeEnum      m_Mode{ ModeEnum::Natural };
  double        m_EffectiveEnergyInKeV{ 60.0 };
  double        m_MuWaterPerMillimeter{ 0.02059 };
  PointListType m_PiecewiseLinearPoints;
  double        m_AirThreshold{ -std::numeric_limits<double>::infinity() };

  DRRMaterialTable::Pointer m_MaterialTable;
  // (mu/rho)_m(E_ref), cm^2/g, valid while the table's modification time is m_MaterialCacheTime and E_ref is
  // m_MaterialCacheEnergyInKeV; otherwise Evaluate() asks the table (thread-safe, slower).
  std::vector<double> m_MassAttenuationAtReference;
  ModifiedTimeType    m_MaterialCacheTime{ 0 };
  double              m_MaterialCacheEnergyInKeV{ 0.0 };
};
} // namespace itk

#endif
