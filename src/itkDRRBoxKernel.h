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
#ifndef itkDRRBoxKernel_h
#define itkDRRBoxKernel_h

#include "itkDRRPhiloxRandom.h"
#include "itkPointBasedDRREnums.h"

namespace itk
{
/** \class DRRBoxKernel
 * \brief Reconstruction-kernel policy: a point uniform inside its voxel (the piecewise-constant model, whose exact
 * projection is Siddon's). Offsets are in voxels, per axis.
 *
 * A kernel policy provides who it is (Id, its enumerator; Name, its registered name; ExactReference, the name of the
 * exact projector of its model, or null if it has none), Reach (how far from the voxel centre a point can go, voxels)
 * and Offset(bits), the offset along one axis from 32 random bits. A new kernel is its
 * own header, an enumerator in PointBasedDRREnums::ReconstructionKernel and one line in DRRPolicies::Kernels
 * (itkDRRPolicies.h).
 *
 * \ingroup PointBasedDRR
 */
struct DRRBoxKernel
{
  /** The enumerator that selects this kernel. */
  static constexpr PointBasedDRREnums::ReconstructionKernel Id = PointBasedDRREnums::ReconstructionKernel::Box;
  /** Its name: the enumerator prints as its CamelCase (DRRPolicyList::GetEnumeratorName()). */
  static constexpr const char * Name = "box";
  /** The exact projector of the box model: Siddon's traversal. */
  static constexpr const char * ExactReference = "siddon";

  /** A point stays within half a voxel of its voxel centre along each axis. */
  static constexpr double Reach = 0.5;

  /** Offset along one axis, voxels: uniform in [-0.5, 0.5) from 32 random bits. */
  static double
  Offset(uint32_t bits)
  {
    return detail::DRRPhiloxRandom::ToUnitInterval(bits) - 0.5;
  }
};
} // namespace itk

#endif
