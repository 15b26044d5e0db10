#pragma once
// Structural checks of every message type, applied by the Bus before any
// handler sees a message: counts match arrays, sizes and indices are in
// range, codes and actions are valid, floats are finite. Checks that need
// context (does a shard fit its job's table?) are made by the receiver.
// Each returns Ok when the message is valid, else an Error of code kCorrupt
// saying what is wrong (its message is what the receiver logs and counts).

#include "dynapath/changes_t.hpp"
#include "dynapath/fragment_nack_t.hpp"
#include "dynapath/fragment_t.hpp"
#include "dynapath/goal_reply_t.hpp"
#include "dynapath/goal_request_t.hpp"
#include "dynapath/grid_t.hpp"
#include "dynapath/heartbeat_t.hpp"
#include "dynapath/job_batch_t.hpp"
#include "dynapath/job_result_t.hpp"
#include "dynapath/limits.h"
#include "dynapath/model_round_t.hpp"
#include "dynapath/model_shards_t.hpp"
#include "dynapath/obstacle_points_t.hpp"
#include "dynapath/obstacle_update_t.hpp"
#include "dynapath/occupancy_grid_t.hpp"
#include "dynapath/path_reply_t.hpp"
#include "dynapath/path_request_t.hpp"
#include "dynapath/policy_t.hpp"
#include "dynapath/result.h"
#include "dynapath/shards_t.hpp"
#include "dynapath/step_report_t.hpp"
#include "dynapath/step_request_t.hpp"

namespace dynapath::protocol {

// The largest grid side the protocol accepts is dynapath::kMaxGridSide
// (core/include/dynapath/limits.h), the same limit as the command line's and the configs'.

Status Validate(const heartbeat_t& message);
Status Validate(const step_request_t& message);
Status Validate(const grid_t& message);
Status Validate(const changes_t& message);
Status Validate(const job_batch_t& message);
Status Validate(const shards_t& message);
Status Validate(const job_result_t& message);
Status Validate(const fragment_t& message);
Status Validate(const fragment_nack_t& message);
Status Validate(const step_report_t& message);
Status Validate(const policy_t& message);
// A federated training of convQ's model: sizes within the training
// command's bounds and kMaxModelLearners, every weight finite and inside
// the model's bounds (CheckConvQModel), squared errors finite and >= 0.
Status Validate(const model_round_t& message);
Status Validate(const model_shards_t& message);
// dynapath serve's messages: structure and the protocol's caps only; whether
// the cells lie inside the service's grid and what they change is checked
// against that grid (protocol/convert.h, ServiceUpdates), so that the
// service counts each refusal by its reason. Coordinates, resolutions and
// origins must be finite (a resolution > 0).
Status Validate(const obstacle_update_t& message);
Status Validate(const obstacle_points_t& message);
Status Validate(const occupancy_grid_t& message);
Status Validate(const path_request_t& message);
Status Validate(const path_reply_t& message);
Status Validate(const goal_request_t& message);
Status Validate(const goal_reply_t& message);

}  // namespace dynapath::protocol
