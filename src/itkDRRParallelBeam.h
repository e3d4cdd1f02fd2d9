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
#ifndef itkDRRParallelBeam_h
#define itkDRRParallelBeam_h

#include "itkPointBasedDRREnums.h"

namespace itk
{
/** \class DRRParallelBeam
 * \brief Beam policy: one line through every pixel along the detector normal, no source; every point has weight 1.
 *
 * \sa DRRPerspectiveBeam for the policy's interface.
 * \ingroup PointBasedDRR
 */
struct DRRParallelBeam
{
  /** The enumerator that selects this beam. */
  static constexpr PointBasedDRREnums::Projection Id = PointBasedDRREnums::Projection::Parallel;
  /** Its name: the enumerator prints as its CamelCase; geometry files spell the beam by it. */
  static constexpr const char * Name = "parallel";
  /** No source: whole lines along the normal (DRRPointProjection's parallel path). */
  static constexpr bool HasSource = false;
  /** No magnification. */
  static constexpr bool MagnifiesRows = false;
};
} // namespace itk

#endif
