// VTK's threading backend and its thread count, alone in a C++17 unit: VTK 9.1's vtkSMPTools.h is not valid C++20.
#include <string>

#include <vtkSMPTools.h>

namespace dentsim::bench {

std::string vtkSmpBackend() { return vtkSMPTools::GetBackend(); }
int vtkSmpThreads() { return vtkSMPTools::GetEstimatedNumberOfThreads(); }

}  // namespace dentsim::bench
