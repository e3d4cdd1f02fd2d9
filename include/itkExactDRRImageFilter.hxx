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
#ifndef itkExactDRRImageFilter_hxx
#define itkExactDRRImageFilter_hxx

#include "itkExactDRRImageFilter.h"
#include "itkDRRExactRayIntegrator.h"

#include <algorithm>
#include <sstream>

namespace itk
{
template <typename TInputImage, typename TOutputImage>
void
ExactDRRImageFilter<TInputImage, TOutputImage>::GenerateData()
{
  this->UpdateProgress(0.0f);
  if (this->GetNumberOfSlabs() > 1)
  {
    std::vector<double>       channels;
    const std::vector<double> image = this->RenderStreamed(channels);
    this->WriteOutputs(image);
    this->WriteChannelOutputs(this->GetChannelLabels().size() == 1 ? image : channels, nullptr);
    this->UpdateProgress(1.0f);
    return;
  }
  const DRRPointProjection    projection = this->MakeProjection();
  const DRRExactRayIntegrator integrator(*this->GetAttenuationVolume(), m_ReconstructionKernel);
  std::vector<double>         channels;
  const std::vector<double>   image =
    integrator.RenderProjection(projection, m_RaysPerPixelSide, this->GetMultiThreader(), this, &channels);
  this->WriteOutputs(image);
  // One channel is the image itself; an exact projection has no estimation error (a covariance of zeros).
  this->WriteChannelOutputs(this->GetChannelLabels().size() == 1 ? image : channels, nullptr);
  this->UpdateProgress(1.0f);
}

template <typename TInputImage, typename TOutputImage>
std::string
ExactDRRImageFilter<TInputImage, TOutputImage>::WhyNotStreamable() const
{
  const std::string why = Superclass::WhyNotStreamable();
  if (!why.empty() || m_ReconstructionKernel == KernelEnum::Box)
  {
    return why;
  }
  std::ostringstream text;
  text << "streaming needs the box kernel: a tent voxel reaches into the next slab, not " << m_ReconstructionKernel;
  return text.str();
}

template <typename TInputImage, typename TOutputImage>
std::vector<double>
ExactDRRImageFilter<TInputImage, TOutputImage>::RenderStreamed(std::vector<double> & channels)
{
  const unsigned int  slabs = this->GetNumberOfSlabs();
  MultiThreaderBase * threader = this->GetMultiThreader();
  std::vector<double> image;
  for (unsigned int slab = 0; slab < slabs; ++slab)
  {
    const DRRAttenuationVolume::Pointer volume = this->ReadSlab(slab);
    const DRRExactRayIntegrator         integrator(*volume, m_ReconstructionKernel);
    std::vector<double>                 partChannels;
    const std::vector<double>           part =
      integrator.RenderProjection(this->MakeProjection(*volume), m_RaysPerPixelSide, threader, nullptr, &partChannels);
    image.resize(part.size(), 0.0);
    for (size_t p = 0; p < part.size(); ++p)
    {
      image[p] += part[p];
    }
    // The same K channels in every slab: the table's materials, or the labels of the whole label image.
    channels.resize(partChannels.size(), 0.0);
    for (size_t c = 0; c < partChannels.size(); ++c)
    {
      channels[c] += partChannels[c];
    }
    this->UpdateProgress(static_cast<float>(slab + 1) / static_cast<float>(slabs));
  }
  return image;
}

template <typename TInputImage, typename TOutputImage>
void
ExactDRRImageFilter<TInputImage, TOutputImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "ReconstructionKernel: " << m_ReconstructionKernel << std::endl;
  os << indent << "RaysPerPixelSide: " << m_RaysPerPixelSide << std::endl;
}
} // namespace itk

#endif
