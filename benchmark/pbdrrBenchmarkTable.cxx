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
#include "pbdrrBenchmarkTable.h"

#include "itkMultiThreaderBase.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace pbdrr
{
namespace bench
{
namespace
{
std::string
CsvField(const std::string & text)
{
  if (text.find_first_of(",\"\n") == std::string::npos)
    return text;
  std::string quoted = "\"";
  for (char c : text)
    quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

const char * CsvHeader =
  "config,sweep,x,voxels,cols,rows,method,sampler,kernel,splat,samples,rays_per_pixel,model,status,runs,wall_s,"
  "wall_min_s,wall_max_s,cpu_s,peak_rss_mib,peak_extra_mib,hu_to_mu_s,tables_s,table_bytes,"
  "table_bytes_per_nonair_voxel,load_s,render_s,first_render_s,nrmse,max_error,sum_ratio,nrmse_box,max_error_box,sum_"
  "ratio_box,"
  "wall_x_nrmse2,note";

/** The "samples / rays" and "note" cells of a row of the Markdown table. */
std::string
CountCell(const Row & r)
{
  std::string count = r.Samples ? SamplesText(r.Samples)
                                : (r.Rays ? std::to_string(r.Rays) + "x" + std::to_string(r.Rays) + " rays" : "");
  if (r.Method == "preprocess")
  {
    count = "";
  }
  return count;
}

std::string
NoteCell(const Row & r)
{
  std::string note = r.Note;
  if (std::isfinite(r.FirstRender))
    note = "first render " + Format(r.FirstRender, "%.3g") + " s" + (note.empty() ? "" : "; " + note);
  if (r.Method == "preprocess")
    note = "attenuation volume (HU->mu) " + Format(r.HuToMu, "%.3g") + " s + tables " + Format(r.Tables, "%.3g") +
           " s; tables " + Format(r.TableBytes / 1048576.0, "%.4g") + " MiB = " + Format(r.TableBytesPerVoxel, "%.3g") +
           " bytes per non-air voxel";
  else if (r.Method.compare(0, 11, "plastimatch") == 0 && r.Status == "ok")
    note = "load " + Format(r.Time.Load, "%.3g") + " s + render/write " + Format(r.Time.Render, "%.3g") +
           " s (whole process)";
  return note;
}
} // namespace

std::string
Format(double value, const char * format)
{
  if (!std::isfinite(value))
    return "";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

std::string
SamplesText(uint64_t n)
{
  if (n == 0)
    return "";
  const int    e = static_cast<int>(std::floor(std::log10(static_cast<double>(n)) + 1e-9));
  const double m = n / std::pow(10.0, e);
  return Format(m, "%.3g") + "e" + std::to_string(e);
}

void
WriteCsv(const std::string & path, const std::vector<Row> & rows)
{
  std::ofstream out(path);
  out << CsvHeader << "\n";
  for (const Row & r : rows)
  {
    const auto g = [](double v) { return Format(v, "%.6g"); };
    out << CsvField(r.Config) << "," << r.Sweep << "," << g(r.X) << "," << (r.Voxels ? std::to_string(r.Voxels) : "")
        << "," << r.Columns << "," << r.DetectorRows << "," << r.Method << "," << CsvField(r.Sampler) << "," << r.Kernel
        << "," << r.Splat << "," << (r.Samples ? std::to_string(r.Samples) : "") << ","
        << (r.Rays ? std::to_string(r.Rays * r.Rays) : "") << "," << r.Model << "," << CsvField(r.Status) << ","
        << (r.Time.Runs ? std::to_string(r.Time.Runs) : "") << "," << g(r.Time.Wall) << "," << g(r.Time.WallMin) << ","
        << g(r.Time.WallMax) << "," << g(r.Time.Cpu) << "," << Format(r.Time.PeakMiB, "%.1f") << ","
        << Format(r.Time.ExtraMiB, "%.1f") << "," << g(r.HuToMu) << "," << g(r.Tables) << "," << g(r.TableBytes) << ","
        << g(r.TableBytesPerVoxel) << "," << g(r.Time.Load) << "," << g(r.Time.Render) << "," << g(r.FirstRender) << ","
        << g(r.Own.Nrmse) << "," << g(r.Own.MaxError) << "," << Format(r.Own.SumRatio, "%.7f") << "," << g(r.Box.Nrmse)
        << "," << g(r.Box.MaxError) << "," << Format(r.Box.SumRatio, "%.7f") << ","
        << g(r.Time.Wall * r.Own.Nrmse * r.Own.Nrmse) << "," << CsvField(r.Note) << "\n";
  }
}

void
WriteAgreementCsv(const std::string & path, const std::vector<AgreementRow> & rows)
{
  std::ofstream out(path);
  out << "image,against,nrmse,max_error,sum_ratio,pearson_r\n";
  for (const auto & a : rows)
    out << CsvField(a.What) << "," << CsvField(a.Against) << "," << Format(a.E.Nrmse, "%.6g") << ","
        << Format(a.E.MaxError, "%.6g") << "," << Format(a.E.SumRatio, "%.8f") << "," << Format(a.E.Pearson, "%.9f")
        << "\n";
}

void
WriteMarkdownTables(std::ostream & md, const std::vector<Row> & rows, const std::vector<AgreementRow> & agreement)
{
  md << "| method | sampler | kernel | splat | samples / rays | status | runs | wall s | CPU s | peak MiB (+) | "
        "NRMSE | max err | sum ratio | NRMSE vs box | sweep | note |\n"
        "|---|---|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---|\n";
  for (const Row & r : rows)
  {
    md << "| " << r.Method << " | " << r.Sampler << " | " << r.Kernel << " | " << r.Splat << " | " << CountCell(r)
       << " | " << r.Status << " | " << (r.Time.Runs ? std::to_string(r.Time.Runs) : "") << " | "
       << Format(r.Time.Wall, "%.3g") << " | " << Format(r.Time.Cpu, "%.3g") << " | " << Format(r.Time.PeakMiB, "%.0f")
       << (std::isfinite(r.Time.ExtraMiB) ? " (+" + Format(r.Time.ExtraMiB, "%.0f") + ")" : "") << " | "
       << Format(r.Own.Nrmse, "%.3g") << " | " << Format(r.Own.MaxError, "%.3g") << " | "
       << Format(r.Own.SumRatio, "%.5f") << " | " << Format(r.Box.Nrmse, "%.3g") << " | " << r.Sweep
       << (std::isfinite(r.X) && r.Sweep != "samples" ? " " + Format(r.X, "%.6g") : "") << " | " << NoteCell(r)
       << " |\n";
  }
  if (!agreement.empty())
  {
    md << "\n## Agreement\n\n| image | against | NRMSE | max err | sum ratio | Pearson r "
          "|\n|---|---|---:|---:|---:|---:|\n";
    for (const auto & a : agreement)
      md << "| " << a.What << " | " << a.Against << " | " << Format(a.E.Nrmse, "%.3g") << " | "
         << Format(a.E.MaxError, "%.3g") << " | " << Format(a.E.SumRatio, "%.6f") << " | "
         << Format(a.E.Pearson, "%.7f") << " |\n";
  }
}

std::string
LoadAverage()
{
  std::ifstream in("/proc/loadavg");
  std::string   a, b, c;
  in >> a >> b >> c;
  return a + " " + b + " " + c;
}

std::string
MachineText()
{
  std::string   model = "?";
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);)
  {
    if (line.compare(0, 10, "model name") == 0)
    {
      model = line.substr(line.find(':') + 2);
      break;
    }
  }
  double        memory = NaN;
  std::ifstream meminfo("/proc/meminfo");
  for (std::string line; std::getline(meminfo, line);)
  {
    if (line.compare(0, 9, "MemTotal:") == 0)
      memory = std::stod(line.substr(9)) / 1048576.0;
  }
  std::ostringstream text;
  text << model << ", " << sysconf(_SC_NPROCESSORS_ONLN) << " cores, " << Format(memory, "%.1f") << " GiB; ITK threads "
       << itk::MultiThreaderBase::GetGlobalDefaultNumberOfThreads();
  return text.str();
}
} // namespace bench
} // namespace pbdrr
