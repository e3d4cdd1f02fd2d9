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
#ifndef itkDRRRenderReduction_h
#define itkDRRRenderReduction_h

// Private to the renderer (src/): from the workers' integer sums to the image and its standard error.

#include "itkDRRRenderWorkers.h"

namespace itk
{
namespace DRRRendering
{
/** Integer reduction of the workers' sums into the line integrals and their standard errors of result (sized, with
 * SampledRoomMass set): exact, hence independent of the order and of the worker that held each chunk. Blocks of
 * pixels in parallel (each pixel on its own: the same bits on any number of threads); each sum is cleared as it is
 * read, for the workspace's next render. pixelArea: mm^2. With more than one channel, also each channel's line
 * integral and the channels' covariance (result sized by ZeroResult()); the image is then reduced from the channels'
 * integer sums added, the same integers as without channels. */
void
Reduce(DRRPointRenderer::Workspace & workspace,
       const Strata &                strata,
       unsigned int                  numberOfChannels,
       const FixedPoint &            fixedPoint,
       double                        pixelArea,
       MultiThreaderBase *           threader,
       DRRPointRenderer::Result &    result);
} // namespace DRRRendering
} // namespace itk

#endif
