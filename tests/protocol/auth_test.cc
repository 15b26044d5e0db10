#include "protocol/auth.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace dynapath::protocol {
namespace {

RunKey Key(const std::string& text) {
  Result<RunKey> key = KeyFromSecretText(text);
  EXPECT_TRUE(key) << key.error().message;
  return *key;
}

const std::string kSecret = "00112233445566778899aabbccddeeff";
const std::string kChannel = "DYNAPATH/run1/POLICY";

std::vector<uint8_t> Sealed(Sealer& sealer, const std::string& channel,
                            const std::vector<uint8_t>& payload) {
  std::vector<uint8_t> out;
  sealer.Seal(channel, payload.data(), payload.size(), out);
  return out;
}

Verifier::Verdict Check(Verifier& verifier, const std::string& channel,
                        const std::vector<uint8_t>& bytes, int* payload = nullptr) {
  int size = -1;
  const Verifier::Verdict verdict =
      verifier.Check(channel, bytes.data(), static_cast<int>(bytes.size()), &size);
  if (payload != nullptr) *payload = size;
  return verdict;
}

TEST(AuthTest, SealedMessagesVerifyAndGiveBackThePayload) {
  Sealer sealer(Key(kSecret));
  Verifier verifier(Key(kSecret));
  const std::vector<uint8_t> payload = {1, 2, 3, 4, 5, 6, 7};
  const std::vector<uint8_t> sealed = Sealed(sealer, kChannel, payload);
  ASSERT_EQ(sealed.size(), payload.size() + kAuthTrailerBytes);
  EXPECT_TRUE(std::equal(payload.begin(), payload.end(), sealed.begin()));
  int size = -1;
  EXPECT_EQ(Check(verifier, kChannel, sealed, &size), Verifier::Verdict::kOk);
  EXPECT_EQ(size, 7);
  EXPECT_EQ(PayloadSize(sealed.data(), static_cast<int>(sealed.size())), 7);
  // An empty payload is a message too.
  EXPECT_EQ(Check(verifier, kChannel, Sealed(sealer, kChannel, {}), &size), Verifier::Verdict::kOk);
  EXPECT_EQ(size, 0);
}

TEST(AuthTest, AnyChangedBitOrChannelOrKeyFailsTheTag) {
  Sealer sealer(Key(kSecret));
  const std::vector<uint8_t> sealed = Sealed(sealer, kChannel, {9, 8, 7, 6, 5, 4, 3, 2, 1, 0});
  for (size_t byte = 0; byte < sealed.size(); ++byte) {
    for (int bit = 0; bit < 8; ++bit) {
      Verifier verifier(Key(kSecret));  // fresh: no replay state
      std::vector<uint8_t> flipped = sealed;
      flipped[byte] = static_cast<uint8_t>(flipped[byte] ^ (1 << bit));
      ASSERT_EQ(Check(verifier, kChannel, flipped), Verifier::Verdict::kUnauthenticated)
          << "byte " << byte << " bit " << bit;
    }
  }
  Verifier verifier(Key(kSecret));
  EXPECT_EQ(Check(verifier, "DYNAPATH/run1/REPORT", sealed), Verifier::Verdict::kUnauthenticated);
  EXPECT_EQ(Check(verifier, "DYNAPATH/run2/POLICY", sealed), Verifier::Verdict::kUnauthenticated);
  Verifier other(Key(kSecret + "x"));
  EXPECT_EQ(Check(other, kChannel, sealed), Verifier::Verdict::kUnauthenticated);
  Verifier insecure(InsecureKey());
  EXPECT_EQ(Check(insecure, kChannel, sealed), Verifier::Verdict::kUnauthenticated);
  // Truncated, without a trailer, or empty.
  const std::vector<uint8_t> truncated(sealed.begin(), sealed.end() - 1);
  EXPECT_EQ(Check(verifier, kChannel, truncated), Verifier::Verdict::kUnauthenticated);
  const std::vector<uint8_t> bare(sealed.begin(), sealed.end() - kAuthTrailerBytes);
  EXPECT_EQ(Check(verifier, kChannel, bare), Verifier::Verdict::kUnauthenticated);
  EXPECT_EQ(Check(verifier, kChannel, {}), Verifier::Verdict::kUnauthenticated);
  // The original still passes.
  EXPECT_EQ(Check(verifier, kChannel, sealed), Verifier::Verdict::kOk);
}

TEST(AuthTest, InsecureKeyStillAuthenticatesAgainstCorruption) {
  Sealer sealer(InsecureKey());
  Verifier verifier(InsecureKey());
  EXPECT_TRUE(InsecureKey().insecure);
  EXPECT_FALSE(Key(kSecret).insecure);
  std::vector<uint8_t> sealed = Sealed(sealer, kChannel, {1, 2, 3});
  EXPECT_EQ(Check(verifier, kChannel, sealed), Verifier::Verdict::kOk);
  sealed[1] ^= 1;
  EXPECT_EQ(Check(verifier, kChannel, sealed), Verifier::Verdict::kUnauthenticated);
}

TEST(AuthTest, EachMessageIsAcceptedOnceWithinTheWindow) {
  Sealer sealer(Key(kSecret));
  Verifier verifier(Key(kSecret));
  std::vector<std::vector<uint8_t>> messages;
  for (int i = 0; i < 10; ++i) messages.push_back(Sealed(sealer, kChannel, {uint8_t(i)}));
  // Out of order is fine; each once only.
  for (int i : {3, 0, 9, 1, 2, 8, 4, 7, 5, 6}) {
    EXPECT_EQ(Check(verifier, kChannel, messages[i]), Verifier::Verdict::kOk) << i;
  }
  for (int i = 0; i < 10; ++i) {
    EXPECT_EQ(Check(verifier, kChannel, messages[i]), Verifier::Verdict::kReplayed) << i;
  }
  // A message never seen but older than the window is refused: the receiver
  // cannot tell whether it saw it.
  const std::vector<uint8_t> old = Sealed(sealer, kChannel, {42});
  for (uint64_t i = 0; i < Verifier::kReplayWindow; ++i) Sealed(sealer, kChannel, {0});
  const std::vector<uint8_t> newest = Sealed(sealer, kChannel, {43});
  EXPECT_EQ(Check(verifier, kChannel, newest), Verifier::Verdict::kOk);
  EXPECT_EQ(Check(verifier, kChannel, old), Verifier::Verdict::kReplayed);
  // Another sender (another Bus) has a window of its own.
  Sealer second(Key(kSecret));
  EXPECT_NE(second.sender(), sealer.sender());
  EXPECT_EQ(Check(verifier, kChannel, Sealed(second, kChannel, {1})), Verifier::Verdict::kOk);
}

TEST(AuthTest, RemembersABoundedNumberOfSenders) {
  Verifier verifier(Key(kSecret));
  Sealer first(Key(kSecret));
  const std::vector<uint8_t> replay = Sealed(first, kChannel, {1});
  ASSERT_EQ(Check(verifier, kChannel, replay), Verifier::Verdict::kOk);
  ASSERT_EQ(Check(verifier, kChannel, replay), Verifier::Verdict::kReplayed);
  for (size_t i = 0; i < Verifier::kMaxSenders; ++i) {
    Sealer sealer(Key(kSecret));
    ASSERT_EQ(Check(verifier, kChannel, Sealed(sealer, kChannel, {2})), Verifier::Verdict::kOk);
  }
  // The first sender was forgotten: its message is accepted once more (the
  // documented limit of a bounded table: only senders with the key get in).
  EXPECT_EQ(Check(verifier, kChannel, replay), Verifier::Verdict::kOk);
}

TEST(AuthTest, PayloadSizeStripsOnlyATrailer) {
  const std::vector<uint8_t> plain = {1, 2, 3};
  EXPECT_EQ(PayloadSize(plain.data(), 3), 3);
  EXPECT_EQ(PayloadSize(nullptr, 0), 0);
  Sealer sealer(InsecureKey());
  const std::vector<uint8_t> sealed = Sealed(sealer, kChannel, plain);
  EXPECT_EQ(PayloadSize(sealed.data(), static_cast<int>(sealed.size())), 3);
}

TEST(AuthTest, SecretTextMakesTheKey) {
  EXPECT_EQ(Key(kSecret).bytes, Key("  " + kSecret + "\n").bytes);
  EXPECT_NE(Key(kSecret).bytes, Key(kSecret + "0").bytes);
  EXPECT_NE(Key(kSecret).bytes, InsecureKey().bytes);
  Result<RunKey> short_key = KeyFromSecretText("0123456789abcdef0123456789abcde");  // 31
  ASSERT_FALSE(short_key);
  EXPECT_NE(short_key.error().message.find("too short"), std::string::npos);
  EXPECT_FALSE(KeyFromSecretText(std::string(40, ' ')));
  const std::string a = NewSecretText(), b = NewSecretText();
  EXPECT_EQ(a.size(), 64u);
  EXPECT_NE(a, b);
  EXPECT_TRUE(KeyFromSecretText(a));
}

class SecretFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        std::filesystem::temp_directory_path() / ("dynapath_auth_test_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }
  std::filesystem::path dir_;
};

TEST_F(SecretFileTest, NewFileIsPrivateAndReadsBack) {
  const std::string path = Path("run.key");
  ASSERT_TRUE(WriteNewSecretFile(path));
  struct stat info {};
  ASSERT_EQ(stat(path.c_str(), &info), 0);
  EXPECT_EQ(info.st_mode & 0777, 0600u);
  Result<RunKey> key = ReadSecretFile(path);
  ASSERT_TRUE(key) << key.error().message;
  EXPECT_FALSE(key->insecure);
  // Never overwritten.
  Status again = WriteNewSecretFile(path);
  ASSERT_FALSE(again);
  EXPECT_NE(again.error().message.find("exists"), std::string::npos);
  EXPECT_EQ(ReadSecretFile(path)->bytes, key->bytes);
}

TEST_F(SecretFileTest, RefusesOpenMissingTooShortAndHugeFiles) {
  const std::string open_path = Path("open.key");
  std::ofstream(open_path) << kSecret << "\n";
  chmod(open_path.c_str(), 0644);
  Result<RunKey> open_key = ReadSecretFile(open_path);
  ASSERT_FALSE(open_key);
  EXPECT_NE(open_key.error().message.find("chmod 600"), std::string::npos);
  chmod(open_path.c_str(), 0600);
  EXPECT_TRUE(ReadSecretFile(open_path));

  Result<RunKey> missing = ReadSecretFile(Path("missing.key"));
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().message.find("cannot open"), std::string::npos);

  const std::string short_path = Path("short.key");
  std::ofstream(short_path) << "abc\n";
  chmod(short_path.c_str(), 0600);
  Result<RunKey> short_key = ReadSecretFile(short_path);
  ASSERT_FALSE(short_key);
  EXPECT_NE(short_key.error().message.find("too short"), std::string::npos);

  const std::string huge_path = Path("huge.key");
  std::ofstream(huge_path) << std::string(kMaxSecretFileBytes + 1, 'a');
  chmod(huge_path.c_str(), 0600);
  Result<RunKey> huge = ReadSecretFile(huge_path);
  ASSERT_FALSE(huge);
  EXPECT_NE(huge.error().message.find("larger than"), std::string::npos);

  Result<RunKey> directory = ReadSecretFile(dir_.string());
  EXPECT_FALSE(directory);
}

TEST_F(SecretFileTest, ReadsASecretFromAPipe) {
  // How the launcher hands the secret to its children: /dev/fd/N of a pipe.
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  const std::string text = kSecret + "\n";
  ASSERT_EQ(write(fds[1], text.data(), text.size()), static_cast<ssize_t>(text.size()));
  close(fds[1]);
  Result<RunKey> key = ReadSecretFile("/dev/fd/" + std::to_string(fds[0]));
  close(fds[0]);
  ASSERT_TRUE(key) << key.error().message;
  EXPECT_EQ(key->bytes, Key(kSecret).bytes);
}

}  // namespace
}  // namespace dynapath::protocol
