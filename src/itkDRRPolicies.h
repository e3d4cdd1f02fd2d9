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
#ifndef itkDRRPolicies_h
#define itkDRRPolicies_h

#include "itkDRRBilinearSplat.h"
#include "itkDRRBoxKernel.h"
#include "itkDRRLocalizerBeam.h"
#include "itkDRRNearestSplat.h"
#include "itkDRRParallelBeam.h"
#include "itkDRRPerspectiveBeam.h"
#include "itkDRRPolicyList.h"
#include "itkDRRTentKernel.h"

namespace itk
{
/** \class DRRPolicies
 * \brief The registrations of the compile-time policies: one line per policy, here and nowhere else.
 *
 * Everything that lists policies is derived from these lists: the renderer's and exact projector's dispatch
 * (DRRPolicyList::Visit()), the printed names of the enumerators (operator<<), the lookup by name (pbdrr's parsing),
 * and the tests that run every policy. Samplers, which are chosen at run time, are registered in DRRSamplerFactory.
 *
 * \ingroup PointBasedDRR
 */
struct DRRPolicies
{
  /** Reconstruction kernels: where in its voxel a point goes (the first is the default). */
  using Kernels = DRRPolicyList<PointBasedDRREnums::ReconstructionKernel, DRRBoxKernel, DRRTentKernel>;
  /** Splats: how a projected point is deposited on the detector (the first is the default). */
  using Splats = DRRPolicyList<PointBasedDRREnums::Splat, DRRNearestSplat, DRRBilinearSplat>;
  /** Beams: how points and rays reach the detector (the first is the default). */
  using Beams = DRRPolicyList<PointBasedDRREnums::Projection, DRRPerspectiveBeam, DRRParallelBeam, DRRLocalizerBeam>;
};
} // namespace itk

#endif
