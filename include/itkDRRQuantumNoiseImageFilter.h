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
#ifndef itkDRRQuantumNoiseImageFilter_h
#define itkDRRQuantumNoiseImageFilter_h

#include "itkDRRCompatibility.h"
#include "itkImageToImageFilter.h"

namespace itk
{
/** \class DRRQuantumNoiseImageFilter
 * \brief Quantum (photon-counting) noise on a DRR: line integrals in, the line integrals a detector counting Poisson
 * photons would measure out.
 *
 * NumberOfPhotons I0 is the mean count of a pixel with nothing in the beam (per pixel, at the detector). Pixel j of
 * line integral L_j receives a count N_j ~ Poisson(I0 exp(-L_j)) and reads -ln(N_j / I0); a pixel that counts no
 * photon reads as half a photon, ln(2 I0), so the output stays finite. exp(-output) is then the measured transmission
 * N_j / I0, whose mean is exp(-L_j) and variance exp(-L_j) / I0. The counts are drawn from the Philox stream (Seed,
 * pixel index, stream id 3; DRRPoissonSampler), separate from the streams of a render's points (0, 1) and rays (2):
 * the same seed gives the same image on any number of threads.
 *
 * The noise is applied to the estimate: a Monte Carlo DRR adds its own variance, about (T se_L)^2 to the
 * transmission's T / I0 (se_L the estimate's standard error); docs/design.md, section 12.
 *
 * \sa PointBasedDRRImageFilter, DRRPoissonSampler
 * \ingroup PointBasedDRR
 */
template <typename TImage>
class ITK_TEMPLATE_EXPORT DRRQuantumNoiseImageFilter : public ImageToImageFilter<TImage, TImage>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRQuantumNoiseImageFilter);

  /** Standard class type aliases. */
  using Self = DRRQuantumNoiseImageFilter;
  using Superclass = ImageToImageFilter<TImage, TImage>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;
  /** The image type: line integrals (dimensionless) in and out. */
  using ImageType = TImage;
  /** A region of the output. */
  using OutputImageRegionType = typename ImageType::RegionType;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(DRRQuantumNoiseImageFilter);

  /** Largest NumberOfPhotons: 10^12 per pixel. */
  static constexpr double MaximumNumberOfPhotons = 1e12;

  ///@{
  /** I0: photons per pixel at the detector with nothing in the beam (0 < I0 <= 10^12; default 10^4). */
  itkSetMacro(NumberOfPhotons, double);
  itkGetConstMacro(NumberOfPhotons, double);
  ///@}

  ///@{
  /** Key of the counts' random stream (default 0). */
  itkSetMacro(Seed, uint64_t);
  itkGetConstMacro(Seed, uint64_t);
  ///@}

protected:
  DRRQuantumNoiseImageFilter();
  ~DRRQuantumNoiseImageFilter() override = default;

  /** Refuses an I0 outside (0, 10^12], an input pixel that is not finite, and a mean count above
   * DRRPoissonSampler::MaximumMean (a line integral below ln(I0 / 10^15)). */
  void
  BeforeThreadedGenerateData() override;

  /** Draws every pixel's count from its own stream. */
  void
  DynamicThreadedGenerateData(const OutputImageRegionType & region) override;

  /** Prints NumberOfPhotons and Seed. */
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  double   m_NumberOfPhotons{ 1e4 };
  uint64_t m_Seed{ 0 };
};
} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#include "itkDRRQuantumNoiseImageFilter.hxx"
#endif

#endif
