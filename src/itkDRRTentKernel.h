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
#ifndef itkDRRTentKernel_h
#define itkDRRTentKernel_h

#include "itkDRRPhiloxRandom.h"
#include "itkPointBasedDRREnums.h"

#include <algorithm>
#include <cmath>

namespace itk
{
/** \class DRRTentKernel
 * \brief Reconstruction-kernel policy: the voxel centre plus a triangular offset in [-1, 1) per axis, which draws
 * exactly from the trilinear interpolant of the volume padded with one layer of zero voxels.
 *
 * \sa DRRBoxKernel for the policy's interface.
 * \ingroup PointBasedDRR
 */
struct DRRTentKernel
{
  /** The enumerator that selects this kernel. */
  static constexpr PointBasedDRREnums::ReconstructionKernel Id = PointBasedDRREnums::ReconstructionKernel::Tent;
  /** Its name: the enumerator prints as its CamelCase (DRRPolicyList::GetEnumeratorName()). */
  static constexpr const char * Name = "tent";
  /** The exact projector of the trilinear model: the dual-grid traversal with 2-point Gauss-Legendre. */
  static constexpr const char * ExactReference = "trilinear";

  /** A point stays within one voxel of its voxel centre along each axis. */
  static constexpr double Reach = 1.0;

  /** Offset along one axis, voxels, in [-1, 1) with density 1 - |t|: the inverse of its distribution function at the
   * uniform of 32 random bits. */
  static double
  Offset(uint32_t bits)
  {
    // One unconditional square root and a select: vectorizes.
    const double u = detail::DRRPhiloxRandom::ToUnitInterval(bits);
    const double root = std::sqrt(2.0 * std::min(u, 1.0 - u));
    return u < 0.5 ? root - 1.0 : 1.0 - root;
  }
};
} // namespace itk

#endif
