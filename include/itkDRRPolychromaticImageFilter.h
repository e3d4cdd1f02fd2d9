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
#ifndef itkDRRPolychromaticImageFilter_h
#define itkDRRPolychromaticImageFilter_h

#include "itkDRRCompatibility.h"
#include "itkDRRMaterialTable.h"
#include "itkDRRXRaySpectrum.h"
#include "itkImageToImageFilter.h"

#include <vector>

namespace itk
{
/** \class DRRPolychromaticImageFilter
 * \brief A polychromatic DRR from per-material line integrals: the transmission of a spectrum through them.
 *
 * Input: a VectorImage whose component m is L_m, the line integral (dimensionless) of mu_ref restricted to material m
 * of the material table (channel m = material m), mu_ref the attenuation (1/mm) at the reference energy E_ref (keV;
 * the transfer function's effective energy). Since mu_m(E) = rho (mu/rho)_m(E), the line integral of material m at
 * energy E is k_m(E) L_m with k_m(E) = (mu/rho)_m(E) / (mu/rho)_m(E_ref) (xraylib, through the table). Each pixel's
 * transmission of the spectrum S(E) (DRRXRaySpectrum) is
 *   T = sum_E S(E) exp(-sum_m k_m(E) L_m) / sum_E S(E),
 * and the output is -ln T (the polychromatic line integral, default) or T (SetOutputTransmission(true)). -ln T is
 * computed in the log domain: finite for any finite input.
 *
 * With the covariance of the channel estimates (SetCovarianceInput(): a VectorImage of K(K+1)/2 components, the upper
 * triangle row-major, (0,0), (0,1), ..., (0,K-1), (1,1), ..., (K-1,K-1), dimensionless^2):
 * - the second output (GetStandardErrorOutput()) is the standard error of the output by the delta method:
 *   g_m = dT/dL_m = -sum_E S k_m(E) exp(...) / sum_E S, var T = g^T C g; the standard error of -ln T is SE(T) / T.
 *   Without a covariance it is 0.
 * - SetCorrectJensenBias(true) replaces exp(-k.L) by exp(-k.L - k^T C k / 2) at each energy. For Gaussian estimates
 *   L_hat ~ N(L, C), E[exp(-k.L_hat)] = exp(-k.L + k^T C k / 2): the corrected T is then exactly unbiased for T at a
 *   known C, and for other estimates the correction removes the second-order (Jensen) bias
 *   E[exp(-k.L_hat)] = exp(-k.L) (1 + k^T C k / 2 + ...). -ln of the corrected T keeps the second-order bias of the
 *   logarithm (var T / (2 T^2)).
 *
 * Throws, before any output is written, for: no material table or spectrum, a channel count other than the table's
 * number of materials, a covariance image of another size or component count, a non-finite input or covariance
 * (naming the pixel), a negative variance (a covariance diagonal, naming the pixel), or E_ref outside xraylib's range.
 *
 * \sa DRRMaterialTable, DRRXRaySpectrum, DRRTransferFunction::GetMaterialIndex()
 * \ingroup PointBasedDRR
 */
template <typename TChannelImage, typename TOutputImage>
class ITK_TEMPLATE_EXPORT DRRPolychromaticImageFilter : public ImageToImageFilter<TChannelImage, TOutputImage>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRPolychromaticImageFilter);

  /** Standard class type aliases. */
  using Self = DRRPolychromaticImageFilter;
  using Superclass = ImageToImageFilter<TChannelImage, TOutputImage>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;
  /** The channel image (a VectorImage of line integrals, dimensionless), also the covariance image's type. */
  using ChannelImageType = TChannelImage;
  /** The output image: -ln T (dimensionless) or T, and the standard error. */
  using OutputImageType = TOutputImage;
  /** A region of the output. */
  using OutputImageRegionType = typename OutputImageType::RegionType;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(DRRPolychromaticImageFilter);

  ///@{
  /** The material table: channel m is its material m. Required. */
  itkSetConstObjectMacro(MaterialTable, DRRMaterialTable);
  itkGetConstObjectMacro(MaterialTable, DRRMaterialTable);
  ///@}

  ///@{
  /** The X-ray spectrum. Required. */
  itkSetConstObjectMacro(Spectrum, DRRXRaySpectrum);
  itkGetConstObjectMacro(Spectrum, DRRXRaySpectrum);
  ///@}

  ///@{
  /** E_ref, keV: the energy at which the channels' mu_ref was computed (default 60 keV, the transfer function's
   * default effective energy). */
  itkSetMacro(ReferenceEnergyInKeV, double);
  itkGetConstMacro(ReferenceEnergyInKeV, double);
  ///@}

  ///@{
  /** Output T instead of -ln T (default false: -ln T). */
  itkSetMacro(OutputTransmission, bool);
  itkGetConstMacro(OutputTransmission, bool);
  itkBooleanMacro(OutputTransmission);
  ///@}

  ///@{
  /** Second-order (Jensen) bias correction with the covariance (default false; no effect without a covariance). */
  itkSetMacro(CorrectJensenBias, bool);
  itkGetConstMacro(CorrectJensenBias, bool);
  itkBooleanMacro(CorrectJensenBias);
  ///@}

  /** The covariance of the channel estimates (optional; K(K+1)/2 components, upper triangle row-major). */
  void
  SetCovarianceInput(const ChannelImageType * covariance)
  {
    this->ProcessObject::SetNthInput(1, const_cast<ChannelImageType *>(covariance));
  }
  /** The covariance input (null if none). */
  const ChannelImageType *
  GetCovarianceInput() const
  {
    return itkDynamicCastInDebugMode<const ChannelImageType *>(this->ProcessObject::GetInput(1));
  }

  /** The standard error of the output (the second output; 0 without a covariance input). */
  OutputImageType *
  GetStandardErrorOutput()
  {
    return this->GetOutput(1);
  }

  /** k_m(E) = (mu/rho)_m(E) / (mu/rho)_m(E_ref) of the last update: K rows of GetNumberOfBins() energies, row-major
   * (the spectrum's bins of nonzero fluence). */
  const std::vector<double> &
  GetAttenuationRatios() const
  {
    return m_Ratios;
  }

protected:
  DRRPolychromaticImageFilter();
  ~DRRPolychromaticImageFilter() override = default;

  /** Checks the inputs (the class description) and computes the k_m(E) table and the spectrum's weights. */
  void
  BeforeThreadedGenerateData() override;

  /** T, -ln T and the standard error of every pixel of the region. */
  void
  DynamicThreadedGenerateData(const OutputImageRegionType & region) override;

  /** Prints the table, the spectrum, E_ref and the switches. */
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  DRRMaterialTable::ConstPointer m_MaterialTable;
  DRRXRaySpectrum::ConstPointer  m_Spectrum;
  double                         m_ReferenceEnergyInKeV{ 60.0 };
  bool                           m_OutputTransmission{ false };
  bool                           m_CorrectJensenBias{ false };

  // Of the last update: k_m(E) (K x nE, row-major) and the spectrum's normalized weights (nE, nonzero bins only).
  std::vector<double> m_Ratios;
  std::vector<double> m_Weights;
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#include "itkDRRPolychromaticImageFilter.hxx"
#endif

#endif
