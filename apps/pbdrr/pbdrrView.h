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
#ifndef pbdrrView_h
#define pbdrrView_h

#include "pbdrrOptions.h"
#include "pbdrrViewList.h"

#include "itkDRRProjectionGeometry.h"
#include "itkImageBase.h"

namespace pbdrr
{
/** The detector of a view that neither a geometry file nor a flag sizes: 512 x 512 pixels of 1.2 mm. */
constexpr itk::SizeValueType DefaultDetectorPixels = 512;
/** The pixel pitch of a view that neither a geometry file nor --spacing gives, mm. */
constexpr double DefaultDetectorSpacing = 1.2;

/** The one way pbdrr builds a view, in every mode (a single view, a batch's views, a manifest's, --view-index), by
 * layers, each changing only what it names:
 *   1. the defaults: gantry 0, DefaultDetectorPixels at DefaultDetectorSpacing, the isocenter at the volume's centre
 *      (the room origin for a null volume, to check the options before the load), DRRProjectionGeometry's own
 *      otherwise;
 *   2. the geometry file (--geometry: every key it gives);
 *   3. the flags (--sad, --sid, --gantry, --nrm, --vup, --isocenter, --size, --spacing, --offset, --projection);
 *   4. the batch row (a sweep's gantry, a views file's cells): only the fields it holds. A row's gantry replaces the
 *      normal below it, as --gantry does the file's.
 * A row given whole (RTK's XML) is the view itself; --projection-matrix and --geometry-from replace layers 2 and 3
 * (and refuse the flags they would silently drop). Throws UsageError or itk::ExceptionObject for a view that cannot
 * be (SID not beyond SAD, a zero normal, ...). */
itk::DRRProjectionGeometry::Pointer
MakeView(const Options & options, const ViewSpec & row, const itk::ImageBase<3> * volume);

/** The view of the options alone: MakeView() without a batch row. */
itk::DRRProjectionGeometry::Pointer
MakeGeometry(const Options & options, const itk::ImageBase<3> * volume);

/** Where an --angles sweep starts: the gantry of the options' view (--gantry, else the geometry file's, else 0).
 * Throws UsageError if that view's direction is a normal (--nrm, or the file's nrm) that no gantry angle gives: a
 * sweep would silently replace it. */
double
SweepStartDegrees(const Options & options);
} // namespace pbdrr

#endif
