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
#ifndef itkDRRLocalizerBeam_h
#define itkDRRLocalizerBeam_h

#include "itkPointBasedDRREnums.h"

namespace itk
{
/** \class DRRLocalizerBeam
 * \brief Beam policy: a CT localizer (scout, surview, topogram): a fan across the table, parallel along it.
 *
 * The tube stands still while the table moves, so the source moves along the detector's rows direction v: the ray of
 * detector point (u, v) starts at S + v v and ends at the pixel. Columns (u) are a fan from the source, rows (v) are
 * parallel lines. A point at depth z (mm, along the detector normal from the source) landing at (u, v) carries the
 * weight sqrt(SID^2 + u^2) / z (dV = (z / SID) dz du dv across a fan; against (SID / z)^2 sqrt(SID^2 + u^2 + v^2) / SID
 * for a cone: docs/design.md section 5), which makes the point estimate unbiased for the pixel-area average line
 * integral. Only points between the source's line and the detector (0 < z <= SID) count.
 *
 * The detector spacing is on the detector plane, at SID: a scanner stores the localizer's column spacing scaled to the
 * isocenter plane (du_iso = du SAD / SID) and its row spacing as the table's step (a reader of localizer headers
 * converts). A localizer has no 3 x 4 projection matrix (DRRProjectionGeometry::HasProjectionMatrix()). \sa
 * DRRPerspectiveBeam for the policy's interface. \ingroup PointBasedDRR
 */
struct DRRLocalizerBeam
{
  /** The enumerator that selects this beam. */
  static constexpr PointBasedDRREnums::Projection Id = PointBasedDRREnums::Projection::Localizer;
  /** Its name: the enumerator prints as its CamelCase; geometry files spell the beam by it. */
  static constexpr const char * Name = "localizer";
  /** Rays start at a source point, which moves with the row. */
  static constexpr bool HasSource = true;
  /** Rows are parallel: the source moves with them. */
  static constexpr bool MagnifiesRows = false;
};
} // namespace itk

#endif
