// owval: one CLI over the owval libraries. Every subcommand lives in its own cmd_*.cpp.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "command.hpp"
#include "owval/base/atomic_output.hpp"
#include "owval/base/failure.hpp"
#include "owval/base/memory_budget.hpp"
#include "owval/base/number_text.hpp"
#include "owval/base/one_line.hpp"
#include "owval/base/process_settings.hpp"
#include "owval/render/render.hpp"

namespace owval::cli {
namespace {
std::vector<CommandSetUp>& Registry() {
  static std::vector<CommandSetUp> registry;
  return registry;
}
int g_exit_code = 0;

// Digits only, at most 18 of them: "-1" is refused rather than wrapped to 2^64 - 1.
bool IsDigits(const std::string& text) {
  return !text.empty() && text.size() <= 18 &&
         text.find_first_not_of("0123456789") == std::string::npos;
}
CLI::Validator DigitsOnly(const std::string& expected, const std::string& name) {
  return CLI::Validator(
      [expected](std::string& text) {
        return IsDigits(text) ? std::string() : "expected " + expected;
      },
      name);
}
// A validator accepting a finite decimal number (ParseDecimal: strtod also read "0x10" and " 1")
// for which `holds` is true: an infinite threshold would pass every frame, as a NaN one would.
CLI::Validator NumberThat(bool (*holds)(double), const std::string& expected,
                          const std::string& name) {
  return CLI::Validator(
      [holds, expected](std::string& text) {
        const std::optional<double> value = owval::ParseDecimal(text);
        if (value && holds(*value)) return std::string();
        return "expected " + expected + ", found '" + OneLine(text, 40) + "'";
      },
      name);
}
// A path or name given on the command line, not empty (`expected` says what it names).
// Commands read an empty one as "not given" (`predict -o ''` printed and wrote nothing,
// `pipeline -o ''` wrote reports/NAME): it is refused here, where "given" is still known.
CLI::Validator NotEmpty(const std::string& expected, const std::string& name) {
  return CLI::Validator(
      [expected](std::string& text) {
        return text.empty() ? "expected " + expected + ", found an empty one" : std::string();
      },
      name);
}
const CLI::Validator kOutputPath = NotEmpty("a path to write", "PATH");
// Inputs too (--backends, --manifest, --reference, ...): commands read an empty one as "not
// given" (`compare --manifest ''` compared with the defaults).
const CLI::Validator kGivenName = NotEmpty("a path or name", "NAME");
const CLI::Validator kMemorySize = NotEmpty("a size such as 512M or 2G", "SIZE");
const CLI::Validator kParticleIndex = DigitsOnly("a particle index (0, 1, 2, ...)", "INDEX");
const CLI::Validator kCount = DigitsOnly("a whole number >= 0", "COUNT");
const CLI::Validator kPositiveCount(
    [](std::string& text) {
      return IsDigits(text) && text.find_first_not_of('0') != std::string::npos
                 ? std::string()
                 : "expected a whole number >= 1, found '" + OneLine(text, 40) + "'";
    },
    "COUNT");
const CLI::Validator kPositive =
    NumberThat([](double x) { return x > 0; }, "a number > 0", "POSITIVE");
const CLI::Validator kNonNegative =
    NumberThat([](double x) { return x >= 0; }, "a number >= 0", "NON-NEGATIVE");
const CLI::Validator kFraction =
    NumberThat([](double x) { return x >= 0 && x <= 1; }, "a number from 0 to 1", "0..1");

// Every number on owval's command line is decimal. CLI11 reads an integer option's "010" as octal
// and "0x10" as hex (`--particle 010` gated particle 8, `--log-step 010` logged every 8 steps),
// and a number option without a check of its own took strtod's hex floats (`--time 0x10`).
// After an option's own checks (their messages stay), leading zeros are dropped so that CLI11
// reads what was typed. No description: --help is unchanged.
constexpr const char* kDecimalName = "decimal";
CLI::Validator DecimalInteger(bool may_be_negative) {
  return CLI::Validator(
      [may_be_negative](std::string& text) {
        const bool negative = may_be_negative && text.size() > 1 && text[0] == '-';
        const std::string digits = text.substr(negative ? 1 : 0);
        if (!IsDigits(digits))
          return "expected a whole number in decimal digits, found '" + OneLine(text, 40) + "'";
        const std::size_t first = digits.find_first_not_of('0');
        text = (negative ? "-" : "") + (first == std::string::npos ? "0" : digits.substr(first));
        return std::string();
      },
      "", kDecimalName);
}
const CLI::Validator kDecimalNumber(
    [](std::string& text) {
      return owval::ParseDecimal(text)
                 ? std::string()
                 : "expected a decimal number, found '" + OneLine(text, 40) + "'";
    },
    "");
// A text value given empty is refused too: commands read "" as "not given" (`pipeline
// --candidate ''` judged owval's own engine as the candidate, ready; `compare --frames ''` gated
// every frame). Options with a check of their own say what they expected first.
const CLI::Validator kNotEmptyText = NotEmpty("a value", "");

void CheckEveryValue(CLI::App& app) {
  for (CLI::Option* option : app.get_options()) {
    const std::string type = option->get_type_name();
    if (type.rfind("TEXT", 0) == 0) option->check(kNotEmptyText);
    const bool unsigned_integer = type.rfind("UINT", 0) == 0;  // "-1" would wrap to 2^64 - 1
    if (unsigned_integer || type.rfind("INT", 0) == 0) {
      option->check(DecimalInteger(!unsigned_integer));
      option->get_validator(kDecimalName)->non_modifying(false);  // check() appends it unmodifying
    } else if (type.rfind("FLOAT", 0) == 0) {
      option->check(kDecimalNumber);
    }
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) CheckEveryValue(*sub);
}

// CLI11's "A excludes B" and "A requires B" in owval's words; "config" is a positional argument.
std::string UsageLine(const CLI::ParseError& error) {
  const std::string what = error.what();
  const bool excludes = dynamic_cast<const CLI::ExcludesError*>(&error) != nullptr;
  const std::string verb = excludes                                          ? " excludes "
                           : dynamic_cast<const CLI::RequiresError*>(&error) ? " requires "
                                                                             : "";
  const std::size_t at = verb.empty() ? std::string::npos : what.find(verb);
  if (at == std::string::npos) return what;
  const std::string first = what.substr(0, at);
  return (first.rfind('-', 0) == 0 ? first : "the argument " + first) +
         (excludes ? " cannot be given with " : " needs ") + what.substr(at + verb.size());
}
}  // namespace

bool RegisterCommand(CommandSetUp set_up) {
  Registry().push_back(std::move(set_up));
  return true;
}
CLI::App& Bench(CLI::App& app) {
  for (CLI::App* sub : app.get_subcommands([](CLI::App* a) { return a->get_name() == "bench"; }))
    return *sub;
  CLI::App* bench = app.add_subcommand("bench", "Benchmarks (JSON results)");
  bench->require_subcommand(1);
  return *bench;
}
void SetExitCode(int code) { g_exit_code = code; }

const CLI::Validator& ParticleIndex() { return kParticleIndex; }
const CLI::Validator& Count() { return kCount; }
const CLI::Validator& Positive() { return kPositive; }
const CLI::Validator& Fraction() { return kFraction; }
const CLI::Validator& NonNegative() { return kNonNegative; }
const CLI::Validator& OutputPath() { return kOutputPath; }
const CLI::Validator& GivenName() { return kGivenName; }
const CLI::Validator& PositiveCount() { return kPositiveCount; }

void AddTrackFlags(CLI::App* cmd, TrackChoice* flags, const std::string& prefix,
                   const std::string& subject) {
  auto* particle = cmd->add_option("--" + prefix + "particle", flags->particle,
                                   subject + " particle (file order; default 0)")
                       ->check(ParticleIndex());
  cmd->add_option("--" + prefix + "group", flags->group,
                  subject + " group's centroid instead: elastic, liquid or all")
      ->excludes(particle)
      ->check(CLI::IsMember({"elastic", "liquid", "all"}));
  cmd->add_option("--" + prefix + "axis", flags->axis, "x, y or z (default y)")
      ->check(CLI::IsMember({"x", "y", "z"}));
}

std::filesystem::path DataDir() {
  if (const char* dir = std::getenv("OWVAL_DATA_DIR")) return dir;
  return OWVAL_SOURCE_DIR;
}

}  // namespace owval::cli

int main(int argc, char** argv) {
  using namespace owval::cli;
  owval::KeepLargeBuffersOnHeap();
  owval::RemoveTemporariesOnSignal();  // Ctrl-C leaves no ".NAME.tmp.PID.N" behind
  owval::render::SilenceCodecLogging();
  CLI::App app{"owval: validation and benchmark harness for Sibernetic-style particle physics"};
  app.set_version_flag("--version", OWVAL_VERSION);
  bool quiet = false;
  app.add_flag("-q,--quiet", quiet, "No progress lines on stderr");
  std::string max_memory;
  app.add_option("--max-memory", max_memory,
                 "Refuse inputs whose data would need more than SIZE bytes (512M, 2G; default: "
                 "half of physical memory)")
      ->check(kMemorySize);  // `--max-memory ''` ran with the default and said nothing
  app.require_subcommand(1);
  app.fallthrough();
  app.parse_complete_callback([&quiet, &max_memory] {
    owval::SetQuietMode(quiet);
    if (!max_memory.empty())
      owval::SetMemoryBudgetBytes(owval::ParseByteSize(max_memory, "--max-memory"));
  });
  for (const auto& set_up : Registry()) set_up(app);
  CheckEveryValue(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    // CLI11's own text can span lines and echo a whole argument: one short printable line.
    std::fprintf(stderr, "owval: usage: %s (see --help)\n", owval::OneLine(UsageLine(e)).c_str());
    return owval::kExitBadInput;
  } catch (...) {
    const owval::Failure failure = owval::DescribeFailure(std::current_exception());
    std::fprintf(stderr, "owval: %s\n", failure.line.c_str());
    return failure.exit_code;
  }
  return g_exit_code;
}
