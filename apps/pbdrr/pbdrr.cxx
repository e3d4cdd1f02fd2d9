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
// pbdrr: digitally reconstructed radiographs from the command line (see pbdrr --help).
#include "pbdrrApplication.h"
#include "pbdrrMessages.h"
#include "pbdrrRegisterCommand.h"
#include "pbdrrVolumeLoader.h"
#include "itkMacro.h"

#include <csignal>
#include <iostream>

int
main(int argc, char * argv[])
{
  pbdrr::InstallMessageWindow();
  // A write past a file size limit (ulimit -f) fails with EFBIG, as on a full disk, and is reported, instead of
  // killing the process by SIGXFSZ between a file and its rename.
  std::signal(SIGXFSZ, SIG_IGN);
  try
  {
    if (argc > 1 && std::string(argv[1]) == "register")
    {
      const auto options = pbdrr::ParseRegisterCommandLine(std::vector<std::string>(argv + 2, argv + argc));
      pbdrr::SetQuietMessages(options.quiet);
      if (options.help)
      {
        std::cout << pbdrr::RegisterHelpText();
        return 0;
      }
      pbdrr::RunRegister(options);
      return 0;
    }
    const pbdrr::Options options = pbdrr::ParseCommandLine(std::vector<std::string>(argv + 1, argv + argc));
    pbdrr::SetQuietMessages(options.quiet);
    if (options.help)
    {
      std::cout << pbdrr::HelpText();
      return 0;
    }
    if (options.version)
    {
      std::cout << pbdrr::VersionText() << std::endl;
      return 0;
    }
    if (!options.listSeries.empty())
    {
      std::cout << pbdrr::ListDicomSeries(options.listSeries);
      return 0;
    }
    pbdrr::Run(options);
    return 0;
  }
  catch (const pbdrr::UsageError & e)
  {
    std::cerr << "pbdrr: error: " << e.what() << std::endl;
    return 2;
  }
  catch (const itk::ExceptionObject & e)
  {
    std::cerr << "pbdrr: error: " << pbdrr::CleanMessage(e.GetDescription()) << std::endl;
    return 1;
  }
  catch (const std::exception & e)
  {
    std::cerr << "pbdrr: error: " << pbdrr::CleanMessage(e.what()) << std::endl;
    return 1;
  }
}
