#include "runtime/model_file.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

#include "runtime/run_driver.h"
#include "tests/temp_path.h"

namespace dynapath::runtime {
namespace {

ModelFile SomeFile() {
  ModelFile file;
  file.model = ConvQModel{99.5, -1.25, -9.0, 0.875, 0.5};
  file.training.seed = 42;
  file.training.rounds = 3;
  file.training.mazes_per_round = 5;
  file.training.samples_per_maze = 64;
  file.training.min_side = 8;
  file.training.max_side = 12;
  return file;
}

std::string_view ModelView(const std::vector<uint8_t>& bytes) {
  return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

TEST(ModelFileTest, RoundTrip) {
  Result<std::vector<uint8_t>> bytes = EncodeModelFile(SomeFile());
  ASSERT_TRUE(bytes.ok());
  EXPECT_EQ(bytes->size(), kModelFileBytes);
  Result<ModelFile> back = DecodeModelFile(ModelView(*bytes));
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->model, SomeFile().model);
  EXPECT_EQ(back->training.seed, 42u);
  EXPECT_EQ(back->training.mazes_per_round, 5);
  EXPECT_EQ(back->training.max_side, 12);
}

TEST(ModelFileTest, AFederatedTrainingIsVersionTwoWithItsLearnersAndAveraging) {
  ModelFile file = SomeFile();
  file.training.learners = 3;
  file.training.averaging = ConvQAveraging::kImportance;
  Result<std::vector<uint8_t>> bytes = EncodeModelFile(file);
  ASSERT_TRUE(bytes.ok());
  EXPECT_EQ(bytes->size(), kFederatedModelFileBytes);
  EXPECT_EQ((*bytes)[8], 2);  // the version
  Result<ModelFile> back = DecodeModelFile(ModelView(*bytes));
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->model, file.model);
  EXPECT_EQ(back->training.learners, 3);
  EXPECT_EQ(back->training.averaging, ConvQAveraging::kImportance);
  EXPECT_EQ(back->training.max_side, 12);
  for (size_t i = 0; i < bytes->size(); ++i) {
    std::vector<uint8_t> flipped = *bytes;
    flipped[i] ^= 0x01;
    EXPECT_FALSE(DecodeModelFile(ModelView(flipped)).ok()) << "byte " << i;
  }
  // Learners out of bounds, checksum not checked: the bound refuses.
  std::vector<uint8_t> zero = *bytes;
  std::memset(zero.data() + 44, 0, 4);
  Result<ModelFile> read = DecodeModelFile(ModelView(zero), /*verify_checksum=*/false);
  ASSERT_FALSE(read.ok());
  EXPECT_NE(read.error().message.find("federated"), std::string::npos);
  // A version 1 file stays version 1.
  Result<std::vector<uint8_t>> plain = EncodeModelFile(SomeFile());
  ASSERT_TRUE(plain.ok());
  EXPECT_EQ((*plain)[8], 1);
}

TEST(ModelFileTest, EveryFlippedByteTruncationAndExtensionIsRefused) {
  Result<std::vector<uint8_t>> bytes = EncodeModelFile(SomeFile());
  ASSERT_TRUE(bytes.ok());
  for (size_t i = 0; i < bytes->size(); ++i) {
    std::vector<uint8_t> flipped = *bytes;
    flipped[i] ^= 0x01;
    EXPECT_FALSE(DecodeModelFile(ModelView(flipped)).ok()) << "byte " << i;
  }
  std::vector<uint8_t> shorter(bytes->begin(), bytes->end() - 1);
  EXPECT_FALSE(DecodeModelFile(ModelView(shorter)).ok());
  std::vector<uint8_t> longer = *bytes;
  longer.push_back(0);
  EXPECT_FALSE(DecodeModelFile(ModelView(longer)).ok());
  EXPECT_FALSE(DecodeModelFile("DYNAPOL\n").ok());
}

TEST(ModelFileTest, WeightsOutOfBoundsAreNeitherWrittenNorRead) {
  ModelFile file = SomeFile();
  file.model.move_discount = 1.0;  // the iteration would not settle
  EXPECT_FALSE(EncodeModelFile(file).ok());
  Result<std::vector<uint8_t>> bytes = EncodeModelFile(SomeFile());
  ASSERT_TRUE(bytes.ok());
  // The discount's bytes replaced, checksum not checked: the bound refuses.
  const double one = 1.0;
  std::memcpy(bytes->data() + kModelFileBytes - 32 - 16, &one, sizeof one);
  Result<ModelFile> read = DecodeModelFile(ModelView(*bytes), /*verify_checksum=*/false);
  ASSERT_FALSE(read.ok());
  EXPECT_NE(read.error().message.find("move_discount"), std::string::npos);
}

TEST(ModelFileTest, TheShippedFileHoldsTheBuiltInModel) {
  Result<ModelFile> file = ReadModelFile(DYNAPATH_SOURCE_DIR "/docs/examples/models/convq.model");
  ASSERT_TRUE(file.ok()) << file.error().message;
  EXPECT_EQ(file->model, ShippedConvQModel());
  EXPECT_EQ(file->training.seed, 1u);
}

TEST(ModelFileTest, TrainingIsTheSameAtOneAndTwoThreads) {
  ConvQTrainingOptions options;
  options.seed = 5;
  options.rounds = 3;
  options.mazes_per_round = 3;
  options.samples_per_maze = 64;
  options.min_side = 8;
  options.max_side = 12;
  std::vector<std::vector<uint8_t>> files;
  for (int threads : {1, 2}) {
    options.threads = threads;
    Result<ConvQModel> model = TrainConvQModel(options, nullptr, {});
    ASSERT_TRUE(model.ok());
    Result<std::vector<uint8_t>> bytes = EncodeModelFile(ModelFile{*model, options});
    ASSERT_TRUE(bytes.ok());
    files.push_back(*bytes);
  }
  EXPECT_EQ(files[0], files[1]);
}

TEST(ModelFileTest, TrainingRecoversTheMdpFromTdTargets) {
  ConvQTrainingOptions options;
  options.seed = 9;
  options.rounds = 4;
  options.mazes_per_round = 4;
  options.samples_per_maze = 256;
  options.min_side = 10;
  options.max_side = 16;
  int rounds = 0;
  Result<ConvQModel> model =
      TrainConvQModel(options, nullptr, [&](const ConvQTrainingRound&) { ++rounds; });
  ASSERT_TRUE(model.ok());
  EXPECT_EQ(rounds, 4);
  const ConvQModel want = SpecConvQModel();
  // From zero rewards and half discounts to SPEC's weights.
  EXPECT_NEAR(model->station_reward, want.station_reward, 1e-4);
  EXPECT_NEAR(model->free_reward, want.free_reward, 1e-4);
  EXPECT_NEAR(model->blocked_reward, want.blocked_reward, 1e-4);
  EXPECT_NEAR(model->move_discount, want.move_discount, 1e-6);
  EXPECT_NEAR(model->bump_discount, want.bump_discount, 1e-6);
  std::atomic<bool> stop{true};
  Result<ConvQModel> stopped = TrainConvQModel(options, &stop, {});
  ASSERT_FALSE(stopped.ok());
  EXPECT_TRUE(stopped.error().IsCancelled());
}

TEST(ModelFileTest, RunOptionsReadTheModelOrRefuseIt) {
  RunOptions options;
  options.approach = "convQ";
  options.model = DYNAPATH_SOURCE_DIR "/docs/examples/models/convq.model";
  Result<RunPlan> plan = ResolveRunOptions(options);
  ASSERT_TRUE(plan.ok()) << plan.error().message;
  ASSERT_NE(plan->options.convq_model, nullptr);
  EXPECT_EQ(*plan->options.convq_model, ShippedConvQModel());
  EXPECT_NE(RunPlanToml(*plan).find("model = "), std::string::npos);
  options.model = DYNAPATH_SOURCE_DIR "/docs/examples/maps/no-such.model";
  plan = ResolveRunOptions(options);
  ASSERT_FALSE(plan.ok());
  EXPECT_NE(plan.error().message.find("--model"), std::string::npos);
}

}  // namespace
}  // namespace dynapath::runtime
