// Prints what reexecUnderXvfbIfNeeded left it with: "display <DISPLAY> marker <marker>
// args <argv[1]|argv[2]|...>" and exits 0, or prints the display error and exits 3.

#include <cstdlib>
#include <iostream>
#include <string>

#include <plantnbv/common/error.h>
#include <plantnbv/viz/display.h>

int main(int argc, char** argv)
{
  if (!plantnbv::viz::reexecUnderXvfbIfNeeded(argc, argv)) {
    try {
      plantnbv::viz::requireDisplay();
      std::cout << "no re-execution, yet a display\n";
    } catch (const plantnbv::Error& e) {
      std::cout << e.what() << "\n";
    }
    return 3;
  }
  const char* display = std::getenv("DISPLAY");
  const char* marker = std::getenv("PLANTNBV_XVFB_REEXEC");
  std::cout << "display " << (display ? display : "") << " marker "
            << (marker ? marker : "") << " args ";
  for (int i = 1; i < argc; ++i)
    std::cout << (i > 1 ? "|" : "") << argv[i];
  std::cout << "\n";
  return 0;
}
