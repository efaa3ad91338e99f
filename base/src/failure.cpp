#include "owval/base/failure.hpp"

#include <filesystem>

namespace owval {

Failure DescribeFailure(std::exception_ptr error) {
  try {
    std::rethrow_exception(error);
  } catch (const NonFiniteTrajectoryError& e) {
    return {std::string("error: ") + e.what(), kExitGateFailed};
  } catch (const InputError& e) {
    return {std::string("error: ") + e.what(), kExitBadInput};
  } catch (const EnvironmentError& e) {
    return {std::string("environment: ") + e.what(), kExitEnvironment};
  } catch (const SimulationError& e) {
    return {std::string("error: ") + e.what(), kExitGateFailed};
  } catch (const std::filesystem::filesystem_error& e) {
    return {"error: " + DescribeFilesystemError(e), kExitBadInput};
  } catch (const std::exception& e) {
    return {std::string("error: ") + e.what(), kExitBadInput};
  }
}

}  // namespace owval
