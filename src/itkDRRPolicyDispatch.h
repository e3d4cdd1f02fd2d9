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
#ifndef itkDRRPolicyDispatch_h
#define itkDRRPolicyDispatch_h

// Private to the renderer (src/): from a run-time kernel or splat to the policy type its loops are compiled for.

#include "itkDRRBilinearSplat.h"
#include "itkDRRBoxKernel.h"
#include "itkDRRNearestSplat.h"
#include "itkDRRTentKernel.h"
#include "itkMacro.h"
#include "itkPointBasedDRREnums.h"

namespace itk
{
/** The registered splats: calls visit with a value of the splat policy's type. One case per splat. */
template <typename TVisit>
auto
WithSplat(PointBasedDRREnums::Splat splat, TVisit && visit)
{
  switch (splat)
  {
    case PointBasedDRREnums::Splat::Nearest:
      return visit(DRRNearestSplat{});
    case PointBasedDRREnums::Splat::Bilinear:
      return visit(DRRBilinearSplat{});
  }
  itkGenericExceptionMacro("DRRPointRenderer: unknown splat " << splat);
}

/** The registered reconstruction kernels: calls visit with a value of the kernel policy's type. One case per kernel. */
template <typename TVisit>
auto
WithKernel(PointBasedDRREnums::ReconstructionKernel kernel, TVisit && visit)
{
  switch (kernel)
  {
    case PointBasedDRREnums::ReconstructionKernel::Box:
      return visit(DRRBoxKernel{});
    case PointBasedDRREnums::ReconstructionKernel::Tent:
      return visit(DRRTentKernel{});
  }
  itkGenericExceptionMacro("DRRPointRenderer: unknown reconstruction kernel " << kernel);
}
} // namespace itk

#endif
