#pragma once
// The verification experiments of "Adamss: Advanced Anisotropic Mass-Spring System", Sec. 2.8,
// and the statements of its discussion (Sec. 2.9),
// one function per subcommand of bench_adamss (main.cpp). Each takes the arguments after its
// name, writes its CSV (and a PNG through scripts/report's plotting, where it has one) under
// the output folder, prints a summary table, and returns the process exit code.
#include <string>
#include <vector>

namespace tt {
namespace bench_adamss {

using Args = std::vector<std::string>;

int runStretch(const Args& args);           // Sec. 2.8.1: uniaxial stretch against the Hunter law
int runSpringFit(const Args& args);         // Sec. 2.8.1: Table 2.2 springs and a least-squares fit
int runShear(const Args& args);             // Sec. 2.8.1: simple shear, work against energy
int runVolume(const Args& args);            // Sec. 2.8.2: volume preservation under gravity
int runScaling(const Args& args);           // Sec. 2.8.3: time of 1000 implicit steps against size
int runMeshIndependence(const Args& args);  // Sec. 2.1.2: the same stretch on several meshes
int runOscillation(const Args& args);       // Sec. 2.9.3: volume oscillation, explicit vs implicit
int runLocking(const Args& args);           // Secs. 2.9.1-2.9.2: tet locking against p
int runResolution(const Args& args);        // Sec. 2.1.4: a spring cantilever at three resolutions

}  // namespace bench_adamss
}  // namespace tt
