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

namespace itk
{
/** \class DRRBoxKernel
 * \brief Reconstruction-kernel policy: a point uniform inside its voxel (the piecewise-constant model, whose exact
 * projection is Siddon's). Offsets are in voxels, per axis.
 *
 * A kernel policy provides Reach (how far from the voxel centre a point can go, voxels) and Offset(bits), the offset
 * along one axis from 32 random bits. Register a new one with one case in WithKernel() in src/itkDRRPolicyDispatch.h.
 *
 * \ingroup PointBasedDRR
 */
struct DRRBoxKernel
{
  /** A point stays within half a voxel of its voxel centre along each axis. */
  static constexpr double Reach = 0.5;

  /** Offset along one axis, voxels: uniform in [-0.5, 0.5) from 32 random bits. */
  static double
  Offset(uint32_t bits)
  {
    return DRRPhiloxRandom::ToUnitInterval(bits) - 0.5;
  }
};
} // namespace itk

#endif
