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
// The session's choice of estimator for a target error (DRREstimatorChoice) and its exact render.
#include "itkDRRPointRenderSession.h"
#include "itkDRRExactRayIntegrator.h"

namespace itk
{
const DRREstimatorChoice::Candidate &
DRRPointRenderSession::ChooseEstimator(const Request &              request,
                                       const DRRAttenuationVolume & volume,
                                       const DRRPointProjection &   projection,
                                       MultiThreaderBase *          threader)
{
  if (request.ReusePoints && m_Choice && MakeChoiceKey(request, volume) == m_ChoiceMadeFor)
  {
    return m_Chosen;
  }
  DRREstimatorChoice pilot;
  pilot.Measure(volume, request.Settings.Kernel, projection, threader);
  return this->ChooseEstimator(request, volume, pilot);
}

const DRREstimatorChoice::Candidate &
DRRPointRenderSession::ChooseEstimator(const Request &              request,
                                       const DRRAttenuationVolume & volume,
                                       const DRREstimatorChoice &   pilots)
{
  const uint64_t poses = request.GetPosesServed();
  const bool     controlVariate = ControlVariateApplies(request);
  m_Candidates = pilots.ListCandidates(request.TargetError, poses, controlVariate);
  m_Chosen = DRREstimatorChoice::Choose(m_Candidates, request.TargetError, request.MaximumNumberOfSamples);
  m_Choice = std::make_unique<DRREstimatorChoice>(pilots);
  m_ChoiceMadeFor = MakeChoiceKey(request, volume);
  m_ChoiceSettled = false;
  return m_Chosen;
}

DRRPointRenderSession::ChoiceMadeFor
DRRPointRenderSession::MakeChoiceKey(const Request & request, const DRRAttenuationVolume & volume)
{
  return ChoiceMadeFor{ volume.GetMTime(),
                        request.TargetError,
                        request.GetPosesServed(),
                        static_cast<unsigned int>(request.Settings.Kernel),
                        ControlVariateApplies(request),
                        request.MaximumNumberOfSamples,
                        request.Settings.Seed,
                        request.Sampler };
}

const DRREstimatorChoice::Candidate &
DRRPointRenderSession::FallBackToExactRays(const Request & request)
{
  if (!m_Choice)
  {
    itkGenericExceptionMacro("DRRPointRenderSession: FallBackToExactRays() needs ChooseEstimator() first");
  }
  const DRREstimatorChoice::Candidate * fastest =
    DRREstimatorChoice::FindFastest(m_Candidates, request.TargetError, 0, true);
  if (!fastest)
  {
    itkGenericExceptionMacro("DRRPointRenderSession: the points' estimate stopped falling above the target error "
                             << request.TargetError << ", and no exact rays are predicted to reach it");
  }
  m_Chosen = *fastest;
  return m_Chosen;
}

DRRPassCombination::Estimate
DRRPointRenderSession::RenderExact(const Request &              request,
                                   unsigned int                 raysPerSide,
                                   const DRRAttenuationVolume & volume,
                                   const DRRPointProjection &   projection,
                                   MultiThreaderBase *          threader,
                                   ProcessObject *              caller)
{
  if (!m_Choice)
  {
    itkGenericExceptionMacro("DRRPointRenderSession: RenderExact() needs ChooseEstimator() first");
  }
  const DRRExactRayIntegrator  integrator(volume, request.Settings.Kernel);
  DRRPassCombination::Estimate estimate;
  estimate.LineIntegral = integrator.RenderProjection(projection, raysPerSide, threader, caller);
  estimate.StandardError.assign(estimate.LineIntegral.size(), 0.0);
  m_Passes.Clear(); // no pass of points to refine
  m_EstimatedError = m_Choice->GetExactError(raysPerSide);
  return estimate;
}
} // namespace itk
