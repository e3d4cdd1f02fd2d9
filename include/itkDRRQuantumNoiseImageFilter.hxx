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
#ifndef itkDRRQuantumNoiseImageFilter_hxx
#define itkDRRQuantumNoiseImageFilter_hxx

#include "itkDRRPoissonSampler.h"
#include "itkImageRegionConstIteratorWithIndex.h"
#include "itkImageRegionIterator.h"

#include <cmath>

namespace itk
{
template <typename TImage>
DRRQuantumNoiseImageFilter<TImage>::DRRQuantumNoiseImageFilter()
{
  this->DynamicMultiThreadingOn();
}

template <typename TImage>
void
DRRQuantumNoiseImageFilter<TImage>::BeforeThreadedGenerateData()
{
  if (!(m_NumberOfPhotons > 0.0 && m_NumberOfPhotons <= MaximumNumberOfPhotons))
  {
    itkExceptionMacro("the number of photons per pixel (I0) must be in (0, 1e12], got " << m_NumberOfPhotons);
  }
  const ImageType * input = this->GetInput();
  // The smallest line integral whose mean count I0 exp(-L) the sampler takes.
  const double lowest = std::log(m_NumberOfPhotons / detail::DRRPoissonSampler::MaximumMean);
  for (ImageRegionConstIteratorWithIndex<ImageType> it(input, input->GetBufferedRegion()); !it.IsAtEnd(); ++it)
  {
    const double value = static_cast<double>(it.Get());
    if (!std::isfinite(value) || value < lowest)
    {
      itkExceptionMacro("line integral " << value << " at pixel " << it.GetIndex()
                                         << ": quantum noise needs finite line integrals of at least " << lowest
                                         << " (a mean count of at most 1e15 photons)");
    }
  }
}

template <typename TImage>
void
DRRQuantumNoiseImageFilter<TImage>::DynamicThreadedGenerateData(const OutputImageRegionType & region)
{
  const ImageType *              input = this->GetInput();
  ImageType *                    output = this->GetOutput();
  const double                   logPhotons = std::log(m_NumberOfPhotons);
  ImageRegionIterator<ImageType> out(output, region);
  for (ImageRegionConstIteratorWithIndex<ImageType> in(input, region); !in.IsAtEnd(); ++in, ++out)
  {
    // The pixel's own stream, addressed by its offset in the image: the same count on any split into regions.
    const auto                pixel = static_cast<uint64_t>(output->ComputeOffset(in.GetIndex()));
    detail::DRRPhiloxRandom   stream(m_Seed, pixel, 3);
    detail::DRRPoissonSampler sampler(stream);
    const uint64_t            count = sampler.Sample(m_NumberOfPhotons * std::exp(-static_cast<double>(in.Get())));
    const double counted = count > 0 ? static_cast<double>(count) : 0.5; // no photon reads as half a photon
    out.Set(static_cast<typename ImageType::PixelType>(logPhotons - std::log(counted)));
  }
}

template <typename TImage>
void
DRRQuantumNoiseImageFilter<TImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfPhotons: " << m_NumberOfPhotons << std::endl;
  os << indent << "Seed: " << m_Seed << std::endl;
}
} // namespace itk

#endif
