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
// The control experiment behind ITK_GLOBAL_DEFAULT_THREADER=Platform in scripts/sanitize.sh tsan: which of ITK's
// threaders ThreadSanitizer sees through when libITKCommon is not instrumented. Not part of the build:
//
//   g++ -std=c++17 -O1 -g -fsanitize=thread -I/usr/include/ITK-5.2 test/sanitizers/TSanThreaderControl.cxx \
//       -o /tmp/TSanThreaderControl -lITKCommon-5.2 -litkvnl-5.2 -litksys-5.2
//   for t in Platform Pool; do ITK_GLOBAL_DEFAULT_THREADER=$t /tmp/TSanThreaderControl; \
//     ITK_GLOBAL_DEFAULT_THREADER=$t /tmp/TSanThreaderControl race; done
//
// Without an argument the program has no race: each work item writes its own slot, the caller reads them after
// ParallelizeArray() returns. With one, every work item also increments one shared counter: a race.
// Measured (ITK 5.2, GCC 12): Platform: no report; with "race", exactly one, the shared counter. Pool: 4 reports of
// races that do not exist (the caller reading a worker's slot after ParallelizeArray() returned, operator delete of
// the pool's task state vs. the worker: both ordered by a std::future inside libITKCommon, which TSan cannot see);
// with "race", 7: the shared counter, among false ones.
#include "itkMultiThreaderBase.h"

#include <cstdio>
#include <vector>

int
main(int argc, char *[])
{
  const bool racy = argc > 1;
  auto       threader = itk::MultiThreaderBase::New();
  threader->SetMaximumNumberOfThreads(4);
  threader->SetNumberOfWorkUnits(4);
  long              shared = 0;
  std::vector<long> own(4, 0);
  for (int round = 0; round < 3; ++round)
  {
    threader->ParallelizeArray(
      0,
      4,
      [&](itk::SizeValueType i) {
        own[i] += 1;
        if (racy)
        {
          shared += 1;
        }
      },
      nullptr);
    own[0] += own[3]; // after the workers: ordered by the join
  }
  std::printf("%s: %ld %ld\n", threader->GetNameOfClass(), shared, own[0]);
  return 0;
}
