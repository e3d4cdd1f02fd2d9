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
#ifndef itkDRRPerspectiveBeam_h
#define itkDRRPerspectiveBeam_h

#include "itkPointBasedDRREnums.h"

namespace itk
{
/** \class DRRPerspectiveBeam
 * \brief Beam policy: rays from the source point to every pixel (a cone beam; the default).
 *
 * A point at depth z (mm, along the detector normal from the source) landing at (u, v) (mm, from the foot of the
 * normal) carries the perspective weight (SID / z)^2 sqrt(SID^2 + u^2 + v^2) / SID, which makes the point estimate
 * unbiased for the pixel-area average line integral (docs/design.md section 2). Projection and weights are computed by
 * DRRPointProjection; the exact projectors trace the same rays (DRRExactRayIntegrator).
 *
 * A beam policy provides who it is: Id (its enumerator), Name (its registered name, which the geometry file's
 * `projection` key takes), HasSource (whether its rays start at a source point) and MagnifiesRows (whether
 * the rows' coordinate of a point is divided by its depth, as the columns' is when there is a source). A new beam is
 * its own header, an enumerator in PointBasedDRREnums::Projection, one line in DRRBeamPolicies (itkDRRPolicies.h), and
 * its projection in DRRPointProjection and DRRExactRayIntegrator.
 *
 * \ingroup PointBasedDRR
 */
struct DRRPerspectiveBeam
{
  /** The enumerator that selects this beam. */
  static constexpr PointBasedDRREnums::Projection Id = PointBasedDRREnums::Projection::Perspective;
  /** Its name: the enumerator prints as its CamelCase; geometry files spell the beam by it. */
  static constexpr const char * Name = "perspective";
  /** Rays start at a source point (projection and weights by DRRPointProjection's perspective path). */
  static constexpr bool HasSource = true;
  /** Rows are magnified as columns are (a cone). */
  static constexpr bool MagnifiesRows = true;
};
} // namespace itk

#endif
