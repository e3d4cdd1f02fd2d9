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

namespace itk
{
template <typename TInputImage, typename TOutputImage>
void
ExactDRRImageFilter<TInputImage, TOutputImage>::GenerateData()
{
  this->UpdateProgress(0.0f);
  if (this->GetNumberOfSlabs() > 1)
  {
    this->WriteOutputs(this->RenderStreamed());
    this->WriteChannelOutputs({}, nullptr);
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
unsigned int
ExactDRRImageFilter<TInputImage, TOutputImage>::GetNumberOfSlabs() const
{
  const TInputImage * input = this->GetInput();
  if (!input || m_NumberOfStreamDivisions <= 1)
  {
    return 1;
  }
  const auto planes = input->GetLargestPossibleRegion().GetSize()[2];
  return static_cast<unsigned int>(
    std::min<SizeValueType>(m_NumberOfStreamDivisions, std::max<SizeValueType>(planes, 1)));
}

template <typename TInputImage, typename TOutputImage>
auto
ExactDRRImageFilter<TInputImage, TOutputImage>::GetSlabRegion(unsigned int slab) const ->
  typename TInputImage::RegionType
{
  auto           region = this->GetInput()->GetLargestPossibleRegion();
  const uint64_t planes = region.GetSize()[2];
  const uint64_t slabs = this->GetNumberOfSlabs();
  const uint64_t first = planes * slab / slabs;
  const uint64_t end = planes * (slab + 1) / slabs;
  region.SetIndex(2, region.GetIndex()[2] + static_cast<IndexValueType>(first));
  region.SetSize(2, static_cast<SizeValueType>(end - first));
  return region;
}

template <typename TInputImage, typename TOutputImage>
void
ExactDRRImageFilter<TInputImage, TOutputImage>::GenerateInputRequestedRegion()
{
  Superclass::GenerateInputRequestedRegion();
  if (this->GetNumberOfSlabs() > 1)
  {
    const_cast<TInputImage *>(this->GetInput())->SetRequestedRegion(this->GetSlabRegion(0));
  }
}

template <typename TInputImage, typename TOutputImage>
void
ExactDRRImageFilter<TInputImage, TOutputImage>::VerifyPreconditions() const
{
  Superclass::VerifyPreconditions();
  if (m_NumberOfStreamDivisions <= 1)
  {
    return;
  }
  if (m_ReconstructionKernel != KernelEnum::Box)
  {
    itkExceptionMacro("streaming needs the box kernel: a tent voxel reaches into the next slab, not "
                      << m_ReconstructionKernel);
  }
  if (!this->GetInput())
  {
    itkExceptionMacro("streaming reads the input volume slab by slab: a shared attenuation volume is already whole");
  }
  if (this->GetLabelImage() || this->GetLabelChannels() || this->GetMaterialChannels())
  {
    itkExceptionMacro("streaming renders without labels or channels (a slab's labels would be resampled apart)");
  }
}

template <typename TInputImage, typename TOutputImage>
std::vector<double>
ExactDRRImageFilter<TInputImage, TOutputImage>::RenderStreamed()
{
  auto *              input = const_cast<TInputImage *>(this->GetInput());
  const auto          largest = input->GetLargestPossibleRegion();
  const unsigned int  slabs = this->GetNumberOfSlabs();
  std::vector<double> image;
  for (unsigned int slab = 0; slab < slabs; ++slab)
  {
    // The slab from upstream: a streaming reader reads it alone, an image in memory is already there.
    const auto region = this->GetSlabRegion(slab);
    input->SetRequestedRegion(region);
    input->PropagateRequestedRegion();
    input->UpdateOutputData();
    const auto buffered = input->GetBufferedRegion();
    if (!buffered.IsInside(region) || buffered.GetSize()[0] != largest.GetSize()[0] ||
        buffered.GetSize()[1] != largest.GetSize()[1])
    {
      itkExceptionMacro("the input's source gave " << buffered << " for the slab " << region
                                                   << ": a slab must be buffered in whole z planes");
    }
    auto                             volume = DRRAttenuationVolume::New();
    DRRAttenuationVolume::MatrixType indexToPhysical;
    for (unsigned int r = 0; r < 3; ++r)
    {
      for (unsigned int c = 0; c < 3; ++c)
      {
        indexToPhysical[r][c] = input->GetDirection()[r][c] * input->GetSpacing()[c];
      }
    }
    typename TInputImage::PointType first;
    input->TransformIndexToPhysicalPoint(region.GetIndex(), first);
    volume->SetIndexToPhysical(indexToPhysical, DRRAttenuationVolume::PointType(first));
    const size_t plane = buffered.GetSize()[0] * buffered.GetSize()[1];
    const auto * values =
      input->GetBufferPointer() + plane * static_cast<size_t>(region.GetIndex()[2] - buffered.GetIndex()[2]);
    MultiThreaderBase * threader = this->GetMultiThreader();
    threader->SetNumberOfWorkUnits(this->GetNumberOfWorkUnits());
    volume->Build(values,
                  { { region.GetSize()[0], region.GetSize()[1], region.GetSize()[2] } },
                  *this->GetTransferFunction(),
                  threader,
                  input->GetPixelContainer());
    const DRRExactRayIntegrator integrator(*volume, m_ReconstructionKernel);
    const std::vector<double>   part =
      integrator.RenderProjection(this->MakeProjection(*volume), m_RaysPerPixelSide, threader, nullptr);
    image.resize(part.size(), 0.0);
    for (size_t p = 0; p < part.size(); ++p)
    {
      image[p] += part[p];
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
  os << indent << "NumberOfStreamDivisions: " << m_NumberOfStreamDivisions << std::endl;
}
} // namespace itk

#endif
