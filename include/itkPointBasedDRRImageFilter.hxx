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
#ifndef itkPointBasedDRRImageFilter_hxx
#define itkPointBasedDRRImageFilter_hxx

#include "itkPointBasedDRRImageFilter.h"
#include "itkDRRLevelAliasSampler.h"

namespace itk
{
template <typename TInputImage, typename TOutputImage>
PointBasedDRRImageFilter<TInputImage, TOutputImage>::PointBasedDRRImageFilter()
  : m_Sampler(DRRLevelAliasSampler::New().GetPointer())
{
  this->SetNumberOfRequiredOutputs(2);
  this->SetNthOutput(1, this->MakeOutput(1));
}

template <typename TInputImage, typename TOutputImage>
ModifiedTimeType
PointBasedDRRImageFilter<TInputImage, TOutputImage>::GetMTime() const
{
  ModifiedTimeType latest = Superclass::GetMTime();
  if (m_Sampler)
  {
    latest = std::max(latest, m_Sampler->GetMTime());
  }
  return latest;
}

template <typename TInputImage, typename TOutputImage>
void
PointBasedDRRImageFilter<TInputImage, TOutputImage>::PrepareSampling()
{
  if (!m_Sampler)
  {
    itkExceptionMacro("no sampler set");
  }
  const DRRAttenuationVolume * volume = this->GetAttenuationVolume();
  if (m_SamplerVolume != volume || m_SamplerVolumeTime != volume->GetMTime() || m_SamplerTime != m_Sampler->GetMTime())
  {
    m_Sampler->Initialize(*volume);
    m_SamplerVolume = volume;
    m_SamplerVolumeTime = volume->GetMTime();
    m_SamplerTime = m_Sampler->GetMTime();
  }
}

template <typename TInputImage, typename TOutputImage>
void
PointBasedDRRImageFilter<TInputImage, TOutputImage>::GenerateData()
{
  if (m_NumberOfSamples == 0)
  {
    itkExceptionMacro("the number of samples must be at least 1");
  }
  this->PrepareSampling();
  const DRRAttenuationVolume * volume = this->GetAttenuationVolume();

  DRRPointRenderer::Settings settings;
  settings.NumberOfSamples = m_NumberOfSamples;
  settings.Seed = m_Seed;
  settings.Kernel = m_ReconstructionKernel;
  settings.Splat = m_Splat;
  settings.Weighting = m_PointWeighting;
  this->UpdateProgress(0.0f);
  const DRRPointRenderer::Result result =
    DRRPointRenderer::Render(*volume, *m_Sampler, this->MakeProjection(), settings, this->GetMultiThreader(), this);
  if (result.SourceNearVolume)
  {
    itkWarningMacro("the volume reaches within " << result.MinimumDepth
                                                 << " mm of the source plane (source inside or next to the volume): "
                                                    "points nearer than that were dropped, the perspective weights "
                                                    "are very large and the standard error is unreliable there");
  }
  m_TotalMass = result.RoomMass;
  m_PointsOnDetector = result.PointsOnDetector;
  this->WriteOutputs(result.LineIntegral, &result.StandardError);
  this->UpdateProgress(1.0f);
}

template <typename TInputImage, typename TOutputImage>
void
PointBasedDRRImageFilter<TInputImage, TOutputImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfSamples: " << m_NumberOfSamples << std::endl;
  os << indent << "Seed: " << m_Seed << std::endl;
  os << indent << "ReconstructionKernel: " << m_ReconstructionKernel << std::endl;
  os << indent << "Splat: " << m_Splat << std::endl;
  os << indent << "PointWeighting: " << m_PointWeighting << std::endl;
  os << indent << "Sampler: " << (m_Sampler ? m_Sampler->GetNameOfClass() : "(none)") << std::endl;
  os << indent << "TotalMass (mm^2): " << m_TotalMass << std::endl;
  os << indent << "PointsOnDetector: " << m_PointsOnDetector << std::endl;
}
} // namespace itk

#endif
