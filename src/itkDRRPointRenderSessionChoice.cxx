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
  const uint64_t      poses = request.ReusePoints ? request.ExpectedNumberOfPoses : 1;
  const bool          controlVariate = ControlVariateApplies(request);
  const ChoiceMadeFor madeFor{ volume.GetMTime(),
                               request.TargetError,
                               poses,
                               static_cast<unsigned int>(request.Settings.Kernel),
                               controlVariate,
                               request.MaximumNumberOfSamples,
                               request.Settings.Seed,
                               request.Sampler };
  if (request.ReusePoints && m_Choice && madeFor == m_ChoiceMadeFor)
  {
    return m_Chosen;
  }
  auto choice = std::make_unique<DRREstimatorChoice>();
  choice->Measure(volume, request.Settings.Kernel, projection, threader);
  m_Chosen = choice->Choose(request.TargetError, poses, controlVariate, request.MaximumNumberOfSamples);
  m_Choice = std::move(choice);
  m_ChoiceMadeFor = madeFor;
  m_ChoiceSettled = false;
  return m_Chosen;
}

const DRREstimatorChoice::Candidate &
DRRPointRenderSession::FallBackToExactRays(const Request & request)
{
  if (!m_Choice)
  {
    itkGenericExceptionMacro("DRRPointRenderSession: FallBackToExactRays() needs ChooseEstimator() first");
  }
  const uint64_t                        poses = request.ReusePoints ? request.ExpectedNumberOfPoses : 1;
  const auto                            candidates = m_Choice->ListCandidates(request.TargetError, poses, false);
  const DRREstimatorChoice::Candidate * fastest = nullptr;
  for (const DRREstimatorChoice::Candidate & candidate : candidates)
  {
    if (candidate.Kind == DRREstimatorChoice::Estimator::ExactRays && candidate.Error <= request.TargetError &&
        (!fastest || candidate.Seconds < fastest->Seconds))
    {
      fastest = &candidate;
    }
  }
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
