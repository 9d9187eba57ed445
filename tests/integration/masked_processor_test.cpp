// The same bits whatever the processor offers: glibc chooses its builds of exp, log, sin and cos when a process
// starts, by the processor's features, and GLIBC_TUNABLES=glibc.cpu.hwcaps=... hides features as an older or a
// virtual machine's processor would. Under two such masks — no FMA and AVX2 (pre-2013 Xeons, VMs that hide them),
// and nothing beyond the x86-64 baseline — the C library computes other bits (checked here, so that the test shows
// what it claims), and this build computes the same fingerprint, golden digests, run on threads, and run on two
// workers, one masked and one not, with every job verified: no worker is refused.

#include <gtest/gtest.h>

#include <regex>
#include <string>
#include <vector>

#include "coordinator_run_fixture.h"
#include "loopback_port.h"

namespace {

using namespace poet::testing;
namespace fs = std::filesystem;

struct Mask {
  const char* name;
  const char* tunables;
  const char* hidden_level;  // the glibc-hwcaps level the mask leaves unsupported, as ld.so --help shows it
};

const Mask kMasks[] = {
    {"no_fma_avx2", "glibc.cpu.hwcaps=-AVX2,-FMA", "x86-64-v3"},
    {"baseline",
     "glibc.cpu.hwcaps=-AVX,-AVX2,-FMA,-FMA4,-SSSE3,-SSE4_1,-SSE4_2,-POPCNT,-LZCNT,-MOVBE,-BMI1,-BMI2,"
     "-CMPXCHG16B,-F16C,-XSAVE,-XSAVEC,-AVX512F,-AVX512DQ,-AVX512BW,-AVX512VL,-AVX512CD,-ERMS",
     "x86-64-v2"},
};

ChildOptions masked(const char* tunables) {
  std::vector<std::string> environment = environment_without({"GLIBC_TUNABLES"});
  if (tunables != nullptr) environment.push_back(std::string("GLIBC_TUNABLES=") + tunables);
  return ChildOptions{.environment = environment};
}

// A digest of the C library's exp, log, sin and cos over 200,000 inputs, as Debian's Python computes them.
constexpr char kLibmDigest[] = R"(import hashlib, math, struct
h = hashlib.sha256()
for i in range(1, 200001):
    x = i * 0.0137
    for v in (math.exp(x % 700), math.log(x), math.sin(x), math.cos(x)):
        h.update(struct.pack('<d', v))
print(h.hexdigest()))";

class MaskedProcessorTest : public CoordinatorRunTest {
 protected:
  void SetUp() override {
    CoordinatorRunTest::SetUp();
#if !defined(__x86_64__)
    GTEST_SKIP() << "glibc's hwcaps masks are x86-64's";
#endif
    const ChildOutcome ld = children_.run({"/lib64/ld-linux-x86-64.so.2", "--help"}, root_ / "ld", 30s);
    if (ld.out.find("x86-64-v3 (supported") == std::string::npos)
      GTEST_SKIP() << "this processor has no x86-64-v3 features (FMA, AVX2) to hide: the masks would change nothing";
  }

  ChildOutcome run_masked(std::vector<std::string> args, const std::string& name, const char* tunables) {
    return children_.run(std::move(args), root_ / name, 300s, masked(tunables));
  }
};

TEST_F(MaskedProcessorTest, TheMasksHideFeaturesAndTheCLibraryComputesOtherBits) {
  const ChildOutcome plain = run_masked({"/usr/bin/python3", "-c", kLibmDigest}, "libm", nullptr);
  ASSERT_EQ(plain.code, 0) << plain.err;
  for (const Mask& mask : kMasks) {
    const ChildOutcome ld =
        run_masked({"/lib64/ld-linux-x86-64.so.2", "--help"}, std::string("ld_") + mask.name, mask.tunables);
    EXPECT_EQ(ld.out.find(std::string(mask.hidden_level) + " (supported"), std::string::npos)
        << mask.name << ": glibc still sees " << mask.hidden_level << "\n"
        << ld.out;
    const ChildOutcome libm =
        run_masked({"/usr/bin/python3", "-c", kLibmDigest}, std::string("libm_") + mask.name, mask.tunables);
    ASSERT_EQ(libm.code, 0) << libm.err;
    EXPECT_NE(libm.out, plain.out) << mask.name << ": the C library computed the same bits; the mask changed nothing";
  }
}

// The probe sees arithmetic: the same program with the C library's math computes another arithmetic digest under
// each mask, while this build's stays the same (the next test).
TEST_F(MaskedProcessorTest, TheArithmeticProbeSeesWhatTheCLibraryChanges) {
  const auto arithmetic = [](const std::string& fingerprint) {
    const size_t at = fingerprint.find("arithmetic: ");
    return at == std::string::npos ? std::string() : fingerprint.substr(at, fingerprint.find('\n', at) - at);
  };
  const ChildOutcome plain = run_masked({POET_LIBM_FINGERPRINT_BIN}, "libm_fingerprint", nullptr);
  ASSERT_EQ(plain.code, 0) << plain.err;
  ASSERT_FALSE(arithmetic(plain.out).empty()) << plain.out;
  for (const Mask& mask : kMasks) {
    const ChildOutcome masked_run =
        run_masked({POET_LIBM_FINGERPRINT_BIN}, std::string("libm_fingerprint_") + mask.name, mask.tunables);
    EXPECT_NE(arithmetic(masked_run.out), arithmetic(plain.out)) << mask.name << ": the probe saw no difference";
  }
}

TEST_F(MaskedProcessorTest, FingerprintAndGoldenDigestsAreTheUnmaskedOnes) {
  const ChildOutcome plain = run_masked({POET_COORDINATOR_BIN, "--fingerprint"}, "fingerprint", nullptr);
  ASSERT_EQ(plain.code, 0) << plain.err;
  EXPECT_NE(plain.out.find("arithmetic: "), std::string::npos) << plain.out;
  for (const Mask& mask : kMasks) {
    const ChildOutcome fingerprint =
        run_masked({POET_COORDINATOR_BIN, "--fingerprint"}, std::string("fingerprint_") + mask.name, mask.tunables);
    EXPECT_EQ(fingerprint.out, plain.out) << mask.name;
    const ChildOutcome golden = run_masked({POET_UNIT_TESTS_BIN, "--gtest_filter=Golden.*", "--gtest_brief=1"},
                                           std::string("golden_") + mask.name, mask.tunables);
    EXPECT_EQ(golden.code, 0) << mask.name << "\n" << golden.out << golden.err;
  }
}

TEST_F(MaskedProcessorTest, ARunOnThreadsIsTheUnmaskedOne) {
  const fs::path reference = threads_run();
  for (const Mask& mask : kMasks) {
    const fs::path dir = root_ / mask.name;
    const ChildOutcome run = run_masked({POET_COORDINATOR_BIN, "--config", config_.string(), "--run-dir", dir.string(),
                                         "--quiet", "--status-address", "127.0.0.1:0", "--threads", "2"},
                                        std::string("run_") + mask.name, mask.tunables);
    ASSERT_EQ(run.code, 0) << run.err;
    expect_same_run(reference, dir);
  }
}

// Every job verified (--verify-fraction 1): each answer of the masked worker is compared with the other's, or the
// coordinator's own; none may differ.
TEST_F(MaskedProcessorTest, AMaskedAndAnUnmaskedWorkerCheckingEveryJobGiveTheRunOfThreads) {
  const fs::path reference = threads_run();
  for (const Mask& mask : kMasks) {
    const int port = free_port();
    ASSERT_GT(port, 0);
    const std::string endpoint = "tcp://127.0.0.1:" + std::to_string(port);
    const std::string name = std::string("listen_") + mask.name;
    const pid_t coordinator_pid = coordinator(root_ / name, {"--listen", endpoint, "--verify-fraction", "1"}, name);
    await_log(name, "workers connect to (tcp://)");
    const pid_t plain = children_.start({POET_WORKER_BIN, "--connect", endpoint, "--threads", "1"},
                                        root_ / (name + "_plain"), masked(nullptr));
    const pid_t hidden = children_.start({POET_WORKER_BIN, "--connect", endpoint, "--threads", "1"},
                                         root_ / (name + "_masked"), masked(mask.tunables));
    ASSERT_EQ(wait(coordinator_pid), 0) << read(root_ / (name + ".err"));
    EXPECT_EQ(wait(plain), 0);
    EXPECT_EQ(wait(hidden), 0);
    const std::string log = read(root_ / (name + ".err"));
    // every job was checked, and no answer of either worker differed from another's or the coordinator's
    std::smatch checked;
    ASSERT_TRUE(std::regex_search(log, checked, std::regex(R"(verification: (\d+) answers checked)"))) << log;
    EXPECT_GT(std::stoi(checked[1]), 20) << log;
    EXPECT_NE(log.find(", 0 worker(s) refused for wrong results"), std::string::npos) << log;
    EXPECT_EQ(log.find("refused worker"), std::string::npos) << log;
    EXPECT_EQ(log.find("returned results"), std::string::npos) << log;
    const std::string masked_log = read(root_ / (name + "_masked.err"));
    EXPECT_EQ(masked_log.find("efused"), std::string::npos) << masked_log;
    EXPECT_NE(masked_log.find("arithmetic"), std::string::npos) << masked_log;
    expect_same_run(reference, root_ / name);
  }
}

}  // namespace
