/* UPM wire messages for C and C++ (iceoryx2's C/C++ bindings).
 * GENERATED from the Rust types by ipc-types/tests/c_header.rs: do not edit.
 * The contract around them (services, settings, units, ranges): docs/protocol.md. */
#ifndef UPM_MESSAGES_H
#define UPM_MESSAGES_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
#define UPM_STATIC_ASSERT static_assert
#define UPM_ALIGNOF alignof
#else
#define UPM_STATIC_ASSERT _Static_assert
#define UPM_ALIGNOF _Alignof
#endif

#define UPM_PROTOCOL_VERSION 6u
#define UPM_MAX_PARTS 64
#define UPM_MAX_CURLS 16
#define UPM_MAX_SLOTS 192
#define UPM_MAX_SHAPE_VERTICES 8
#define UPM_MAX_CENTERS 192
#define UPM_RIG_PREFIX_BYTES 64
#define UPM_MAX_PICK_POSES 16
#define UPM_FEED_RECENT_PICKS 16
#define UPM_RECIPE_PATH_BYTES 240
#define UPM_SHAPE_POINT 0u
#define UPM_SHAPE_DISC 1u
#define UPM_SHAPE_POLYGON 2u
#define UPM_SERVICE_PART_STATES "upm/part_states"
#define UPM_SERVICE_FORCE_REQUEST "upm/force_request"
#define UPM_SERVICE_EXPLICIT_SCHEDULE "upm/explicit_schedule"
#define UPM_SERVICE_CORE_COMMAND "upm/core_command"
#define UPM_SERVICE_SCHEDULE "upm/schedule"
#define UPM_SERVICE_TELEMETRY "upm/telemetry"
#define UPM_SERVICE_REJECTION "upm/rejection"
#define UPM_SERVICE_RIG_INFO "upm/rig_info"
#define UPM_SERVICE_SIM_GROUND_TRUTH "upm/sim/ground_truth"
#define UPM_SERVICE_FEED "upm/feed"
#define UPM_SERVICE_PICK "upm/pick"
#define UPM_SERVICE_RECIPE "upm/recipe"
#define UPM_SERVICE_RECIPE_ACTIVE "upm/recipe/active"
#define UPM_SERVICE_LINE "upm/line"
#define UPM_SERVICE_CAMERA_FRAME "upm/camera/frame"
#define UPM_SERVICE_INBOX "upm/inbox"

/* iceoryx2 type name "upm::PartState.v6", 208 bytes, align 8 */
#define UPM_PARTSTATE_TYPE_NAME "upm::PartState.v6"
typedef struct {
    uint32_t id;
    uint32_t class_;
    uint32_t friction_class;
    uint32_t shape;
    double x;
    double y;
    double theta;
    double vx;
    double vy;
    double omega;
    double radius;
    uint32_t vertex_count;
    uint32_t reserved;
    double vertices[8][2];
} upm_PartState;
UPM_STATIC_ASSERT(sizeof(upm_PartState) == 208, "upm_PartState size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_PartState) == 8, "upm_PartState align");
UPM_STATIC_ASSERT(offsetof(upm_PartState, id) == 0, "upm_PartState.id offset");
UPM_STATIC_ASSERT(offsetof(upm_PartState, class_) == 4, "upm_PartState.class_ offset");
UPM_STATIC_ASSERT(offsetof(upm_PartState, friction_class) == 8, "upm_PartState.friction_class offset");
UPM_STATIC_ASSERT(offsetof(upm_PartState, shape) == 12, "upm_PartState.shape offset");
UPM_STATIC_ASSERT(offsetof(upm_PartState, x) == 16, "upm_PartState.x offset");
UPM_STATIC_ASSERT(offsetof(upm_PartState, y) == 24, "upm_PartState.y offset");
UPM_STATIC_ASSERT(offsetof(upm_PartState, theta) == 32, "upm_PartState.theta offset");
UPM_STATIC_ASSERT(offsetof(upm_PartState, vx) == 40, "upm_PartState.vx offset");
UPM_STATIC_ASSERT(offsetof(upm_PartState, vy) == 48, "upm_PartState.vy offset");
UPM_STATIC_ASSERT(offsetof(upm_PartState, omega) == 56, "upm_PartState.omega offset");
UPM_STATIC_ASSERT(offsetof(upm_PartState, radius) == 64, "upm_PartState.radius offset");
UPM_STATIC_ASSERT(offsetof(upm_PartState, vertex_count) == 72, "upm_PartState.vertex_count offset");
UPM_STATIC_ASSERT(offsetof(upm_PartState, reserved) == 76, "upm_PartState.reserved offset");
UPM_STATIC_ASSERT(offsetof(upm_PartState, vertices) == 80, "upm_PartState.vertices offset");

/* iceoryx2 type name "upm::PartStates.v6", 13336 bytes, align 8 */
#define UPM_PARTSTATES_TYPE_NAME "upm::PartStates.v6"
typedef struct {
    uint32_t protocol_version;
    uint32_t count;
    uint64_t seq;
    uint64_t stamp_ns;
    upm_PartState parts[64];
} upm_PartStates;
UPM_STATIC_ASSERT(sizeof(upm_PartStates) == 13336, "upm_PartStates size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_PartStates) == 8, "upm_PartStates align");
UPM_STATIC_ASSERT(offsetof(upm_PartStates, protocol_version) == 0, "upm_PartStates.protocol_version offset");
UPM_STATIC_ASSERT(offsetof(upm_PartStates, count) == 4, "upm_PartStates.count offset");
UPM_STATIC_ASSERT(offsetof(upm_PartStates, seq) == 8, "upm_PartStates.seq offset");
UPM_STATIC_ASSERT(offsetof(upm_PartStates, stamp_ns) == 16, "upm_PartStates.stamp_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_PartStates, parts) == 24, "upm_PartStates.parts offset");

/* iceoryx2 type name "upm::ForceEntry.v6", 40 bytes, align 8 */
#define UPM_FORCEENTRY_TYPE_NAME "upm::ForceEntry.v6"
typedef struct {
    uint32_t part_id;
    uint32_t force_flag;
    uint32_t curl_flag;
    uint32_t reserved;
    double fx;
    double fy;
    double curl;
} upm_ForceEntry;
UPM_STATIC_ASSERT(sizeof(upm_ForceEntry) == 40, "upm_ForceEntry size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_ForceEntry) == 8, "upm_ForceEntry align");
UPM_STATIC_ASSERT(offsetof(upm_ForceEntry, part_id) == 0, "upm_ForceEntry.part_id offset");
UPM_STATIC_ASSERT(offsetof(upm_ForceEntry, force_flag) == 4, "upm_ForceEntry.force_flag offset");
UPM_STATIC_ASSERT(offsetof(upm_ForceEntry, curl_flag) == 8, "upm_ForceEntry.curl_flag offset");
UPM_STATIC_ASSERT(offsetof(upm_ForceEntry, reserved) == 12, "upm_ForceEntry.reserved offset");
UPM_STATIC_ASSERT(offsetof(upm_ForceEntry, fx) == 16, "upm_ForceEntry.fx offset");
UPM_STATIC_ASSERT(offsetof(upm_ForceEntry, fy) == 24, "upm_ForceEntry.fy offset");
UPM_STATIC_ASSERT(offsetof(upm_ForceEntry, curl) == 32, "upm_ForceEntry.curl offset");

/* iceoryx2 type name "upm::ForceRequest.v6", 2592 bytes, align 8 */
#define UPM_FORCEREQUEST_TYPE_NAME "upm::ForceRequest.v6"
typedef struct {
    uint32_t protocol_version;
    uint32_t count;
    uint64_t seq;
    uint64_t stamp_ns;
    uint64_t deadline_ns;
    upm_ForceEntry entries[64];
} upm_ForceRequest;
UPM_STATIC_ASSERT(sizeof(upm_ForceRequest) == 2592, "upm_ForceRequest size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_ForceRequest) == 8, "upm_ForceRequest align");
UPM_STATIC_ASSERT(offsetof(upm_ForceRequest, protocol_version) == 0, "upm_ForceRequest.protocol_version offset");
UPM_STATIC_ASSERT(offsetof(upm_ForceRequest, count) == 4, "upm_ForceRequest.count offset");
UPM_STATIC_ASSERT(offsetof(upm_ForceRequest, seq) == 8, "upm_ForceRequest.seq offset");
UPM_STATIC_ASSERT(offsetof(upm_ForceRequest, stamp_ns) == 16, "upm_ForceRequest.stamp_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_ForceRequest, deadline_ns) == 24, "upm_ForceRequest.deadline_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_ForceRequest, entries) == 32, "upm_ForceRequest.entries offset");

/* iceoryx2 type name "upm::ExplicitSlot.v6", 16 bytes, align 8 */
#define UPM_EXPLICITSLOT_TYPE_NAME "upm::ExplicitSlot.v6"
typedef struct {
    uint32_t center_index;
    uint32_t reserved;
    double k;
} upm_ExplicitSlot;
UPM_STATIC_ASSERT(sizeof(upm_ExplicitSlot) == 16, "upm_ExplicitSlot size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_ExplicitSlot) == 8, "upm_ExplicitSlot align");
UPM_STATIC_ASSERT(offsetof(upm_ExplicitSlot, center_index) == 0, "upm_ExplicitSlot.center_index offset");
UPM_STATIC_ASSERT(offsetof(upm_ExplicitSlot, reserved) == 4, "upm_ExplicitSlot.reserved offset");
UPM_STATIC_ASSERT(offsetof(upm_ExplicitSlot, k) == 8, "upm_ExplicitSlot.k offset");

/* iceoryx2 type name "upm::ExplicitSchedule.v6", 3096 bytes, align 8 */
#define UPM_EXPLICITSCHEDULE_TYPE_NAME "upm::ExplicitSchedule.v6"
typedef struct {
    uint32_t protocol_version;
    uint32_t count;
    uint64_t seq;
    uint64_t stamp_ns;
    upm_ExplicitSlot slots[192];
} upm_ExplicitSchedule;
UPM_STATIC_ASSERT(sizeof(upm_ExplicitSchedule) == 3096, "upm_ExplicitSchedule size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_ExplicitSchedule) == 8, "upm_ExplicitSchedule align");
UPM_STATIC_ASSERT(offsetof(upm_ExplicitSchedule, protocol_version) == 0, "upm_ExplicitSchedule.protocol_version offset");
UPM_STATIC_ASSERT(offsetof(upm_ExplicitSchedule, count) == 4, "upm_ExplicitSchedule.count offset");
UPM_STATIC_ASSERT(offsetof(upm_ExplicitSchedule, seq) == 8, "upm_ExplicitSchedule.seq offset");
UPM_STATIC_ASSERT(offsetof(upm_ExplicitSchedule, stamp_ns) == 16, "upm_ExplicitSchedule.stamp_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_ExplicitSchedule, slots) == 24, "upm_ExplicitSchedule.slots offset");

/* iceoryx2 type name "upm::CoreCommand.v6", 24 bytes, align 8 */
#define UPM_CORECOMMAND_TYPE_NAME "upm::CoreCommand.v6"
typedef struct {
    uint32_t protocol_version;
    uint32_t command;
    uint64_t seq;
    uint64_t stamp_ns;
} upm_CoreCommand;
UPM_STATIC_ASSERT(sizeof(upm_CoreCommand) == 24, "upm_CoreCommand size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_CoreCommand) == 8, "upm_CoreCommand align");
UPM_STATIC_ASSERT(offsetof(upm_CoreCommand, protocol_version) == 0, "upm_CoreCommand.protocol_version offset");
UPM_STATIC_ASSERT(offsetof(upm_CoreCommand, command) == 4, "upm_CoreCommand.command offset");
UPM_STATIC_ASSERT(offsetof(upm_CoreCommand, seq) == 8, "upm_CoreCommand.seq offset");
UPM_STATIC_ASSERT(offsetof(upm_CoreCommand, stamp_ns) == 16, "upm_CoreCommand.stamp_ns offset");

/* iceoryx2 type name "upm::ScheduleSlot.v6", 32 bytes, align 8 */
#define UPM_SCHEDULESLOT_TYPE_NAME "upm::ScheduleSlot.v6"
typedef struct {
    uint32_t center_index;
    uint32_t reserved;
    double x;
    double y;
    double k;
} upm_ScheduleSlot;
UPM_STATIC_ASSERT(sizeof(upm_ScheduleSlot) == 32, "upm_ScheduleSlot size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_ScheduleSlot) == 8, "upm_ScheduleSlot align");
UPM_STATIC_ASSERT(offsetof(upm_ScheduleSlot, center_index) == 0, "upm_ScheduleSlot.center_index offset");
UPM_STATIC_ASSERT(offsetof(upm_ScheduleSlot, reserved) == 4, "upm_ScheduleSlot.reserved offset");
UPM_STATIC_ASSERT(offsetof(upm_ScheduleSlot, x) == 8, "upm_ScheduleSlot.x offset");
UPM_STATIC_ASSERT(offsetof(upm_ScheduleSlot, y) == 16, "upm_ScheduleSlot.y offset");
UPM_STATIC_ASSERT(offsetof(upm_ScheduleSlot, k) == 24, "upm_ScheduleSlot.k offset");

/* iceoryx2 type name "upm::Schedule.v6", 6240 bytes, align 8 */
#define UPM_SCHEDULE_TYPE_NAME "upm::Schedule.v6"
typedef struct {
    uint32_t protocol_version;
    uint32_t count;
    uint64_t seq;
    uint64_t stamp_ns;
    uint64_t cycle;
    uint64_t solve_time_ns;
    uint64_t parts_seq;
    uint64_t parts_stamp_ns;
    uint64_t request_stamp_ns;
    double residual;
    double condition;
    uint32_t rank;
    uint32_t saturated;
    uint32_t at_bound;
    uint32_t reserved;
    upm_ScheduleSlot slots[192];
} upm_Schedule;
UPM_STATIC_ASSERT(sizeof(upm_Schedule) == 6240, "upm_Schedule size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_Schedule) == 8, "upm_Schedule align");
UPM_STATIC_ASSERT(offsetof(upm_Schedule, protocol_version) == 0, "upm_Schedule.protocol_version offset");
UPM_STATIC_ASSERT(offsetof(upm_Schedule, count) == 4, "upm_Schedule.count offset");
UPM_STATIC_ASSERT(offsetof(upm_Schedule, seq) == 8, "upm_Schedule.seq offset");
UPM_STATIC_ASSERT(offsetof(upm_Schedule, stamp_ns) == 16, "upm_Schedule.stamp_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_Schedule, cycle) == 24, "upm_Schedule.cycle offset");
UPM_STATIC_ASSERT(offsetof(upm_Schedule, solve_time_ns) == 32, "upm_Schedule.solve_time_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_Schedule, parts_seq) == 40, "upm_Schedule.parts_seq offset");
UPM_STATIC_ASSERT(offsetof(upm_Schedule, parts_stamp_ns) == 48, "upm_Schedule.parts_stamp_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_Schedule, request_stamp_ns) == 56, "upm_Schedule.request_stamp_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_Schedule, residual) == 64, "upm_Schedule.residual offset");
UPM_STATIC_ASSERT(offsetof(upm_Schedule, condition) == 72, "upm_Schedule.condition offset");
UPM_STATIC_ASSERT(offsetof(upm_Schedule, rank) == 80, "upm_Schedule.rank offset");
UPM_STATIC_ASSERT(offsetof(upm_Schedule, saturated) == 84, "upm_Schedule.saturated offset");
UPM_STATIC_ASSERT(offsetof(upm_Schedule, at_bound) == 88, "upm_Schedule.at_bound offset");
UPM_STATIC_ASSERT(offsetof(upm_Schedule, reserved) == 92, "upm_Schedule.reserved offset");
UPM_STATIC_ASSERT(offsetof(upm_Schedule, slots) == 96, "upm_Schedule.slots offset");

/* iceoryx2 type name "upm::Rejection.v6", 176 bytes, align 8 */
#define UPM_REJECTION_TYPE_NAME "upm::Rejection.v6"
typedef struct {
    uint32_t protocol_version;
    uint32_t kind;
    uint64_t seq;
    uint64_t message_stamp_ns;
    uint64_t stamp_ns;
    uint64_t parts_seq;
    uint64_t parts_stamp_ns;
    uint32_t reason;
    uint32_t reserved;
    uint8_t detail[120];
} upm_Rejection;
UPM_STATIC_ASSERT(sizeof(upm_Rejection) == 176, "upm_Rejection size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_Rejection) == 8, "upm_Rejection align");
UPM_STATIC_ASSERT(offsetof(upm_Rejection, protocol_version) == 0, "upm_Rejection.protocol_version offset");
UPM_STATIC_ASSERT(offsetof(upm_Rejection, kind) == 4, "upm_Rejection.kind offset");
UPM_STATIC_ASSERT(offsetof(upm_Rejection, seq) == 8, "upm_Rejection.seq offset");
UPM_STATIC_ASSERT(offsetof(upm_Rejection, message_stamp_ns) == 16, "upm_Rejection.message_stamp_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_Rejection, stamp_ns) == 24, "upm_Rejection.stamp_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_Rejection, parts_seq) == 32, "upm_Rejection.parts_seq offset");
UPM_STATIC_ASSERT(offsetof(upm_Rejection, parts_stamp_ns) == 40, "upm_Rejection.parts_stamp_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_Rejection, reason) == 48, "upm_Rejection.reason offset");
UPM_STATIC_ASSERT(offsetof(upm_Rejection, reserved) == 52, "upm_Rejection.reserved offset");
UPM_STATIC_ASSERT(offsetof(upm_Rejection, detail) == 56, "upm_Rejection.detail offset");

/* iceoryx2 type name "upm::RigCenter.v6", 24 bytes, align 8 */
#define UPM_RIGCENTER_TYPE_NAME "upm::RigCenter.v6"
typedef struct {
    double x;
    double y;
    double k_bound;
} upm_RigCenter;
UPM_STATIC_ASSERT(sizeof(upm_RigCenter) == 24, "upm_RigCenter size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_RigCenter) == 8, "upm_RigCenter align");
UPM_STATIC_ASSERT(offsetof(upm_RigCenter, x) == 0, "upm_RigCenter.x offset");
UPM_STATIC_ASSERT(offsetof(upm_RigCenter, y) == 8, "upm_RigCenter.y offset");
UPM_STATIC_ASSERT(offsetof(upm_RigCenter, k_bound) == 16, "upm_RigCenter.k_bound offset");

/* iceoryx2 type name "upm::RigInfo.v6", 4848 bytes, align 8 */
#define UPM_RIGINFO_TYPE_NAME "upm::RigInfo.v6"
typedef struct {
    uint32_t protocol_version;
    uint32_t count;
    uint64_t seq;
    uint64_t stamp_ns;
    uint32_t core_pid;
    uint32_t cycle_slots;
    uint32_t class_count;
    uint32_t friction_class_count;
    uint32_t slot_ticks;
    uint32_t reserved;
    uint64_t cycle_period_ns;
    double tick_hz;
    double vision_frame_hz;
    double mu_m_g;
    double plate_half_extent[2];
    double k_max;
    double max_part_force_n;
    double max_part_force_at[2];
    double keep_out_m;
    double saturation_tolerance;
    double saturation_floor;
    double parts_max_age_ms;
    double request_max_age_ms;
    double max_future_skew_ms;
    uint8_t prefix[64];
    upm_RigCenter centers[192];
} upm_RigInfo;
UPM_STATIC_ASSERT(sizeof(upm_RigInfo) == 4848, "upm_RigInfo size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_RigInfo) == 8, "upm_RigInfo align");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, protocol_version) == 0, "upm_RigInfo.protocol_version offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, count) == 4, "upm_RigInfo.count offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, seq) == 8, "upm_RigInfo.seq offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, stamp_ns) == 16, "upm_RigInfo.stamp_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, core_pid) == 24, "upm_RigInfo.core_pid offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, cycle_slots) == 28, "upm_RigInfo.cycle_slots offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, class_count) == 32, "upm_RigInfo.class_count offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, friction_class_count) == 36, "upm_RigInfo.friction_class_count offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, slot_ticks) == 40, "upm_RigInfo.slot_ticks offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, reserved) == 44, "upm_RigInfo.reserved offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, cycle_period_ns) == 48, "upm_RigInfo.cycle_period_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, tick_hz) == 56, "upm_RigInfo.tick_hz offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, vision_frame_hz) == 64, "upm_RigInfo.vision_frame_hz offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, mu_m_g) == 72, "upm_RigInfo.mu_m_g offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, plate_half_extent) == 80, "upm_RigInfo.plate_half_extent offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, k_max) == 96, "upm_RigInfo.k_max offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, max_part_force_n) == 104, "upm_RigInfo.max_part_force_n offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, max_part_force_at) == 112, "upm_RigInfo.max_part_force_at offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, keep_out_m) == 128, "upm_RigInfo.keep_out_m offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, saturation_tolerance) == 136, "upm_RigInfo.saturation_tolerance offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, saturation_floor) == 144, "upm_RigInfo.saturation_floor offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, parts_max_age_ms) == 152, "upm_RigInfo.parts_max_age_ms offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, request_max_age_ms) == 160, "upm_RigInfo.request_max_age_ms offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, max_future_skew_ms) == 168, "upm_RigInfo.max_future_skew_ms offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, prefix) == 176, "upm_RigInfo.prefix offset");
UPM_STATIC_ASSERT(offsetof(upm_RigInfo, centers) == 240, "upm_RigInfo.centers offset");

/* iceoryx2 type name "upm::FrameHeader.v6", 48 bytes, align 8 */
#define UPM_FRAMEHEADER_TYPE_NAME "upm::FrameHeader.v6"
typedef struct {
    uint32_t protocol_version;
    uint32_t pixel_format;
    uint32_t width;
    uint32_t height;
    uint32_t stride;
    uint32_t reserved;
    uint64_t seq;
    uint64_t stamp_ns;
    uint64_t exposure_ns;
} upm_FrameHeader;
UPM_STATIC_ASSERT(sizeof(upm_FrameHeader) == 48, "upm_FrameHeader size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_FrameHeader) == 8, "upm_FrameHeader align");
UPM_STATIC_ASSERT(offsetof(upm_FrameHeader, protocol_version) == 0, "upm_FrameHeader.protocol_version offset");
UPM_STATIC_ASSERT(offsetof(upm_FrameHeader, pixel_format) == 4, "upm_FrameHeader.pixel_format offset");
UPM_STATIC_ASSERT(offsetof(upm_FrameHeader, width) == 8, "upm_FrameHeader.width offset");
UPM_STATIC_ASSERT(offsetof(upm_FrameHeader, height) == 12, "upm_FrameHeader.height offset");
UPM_STATIC_ASSERT(offsetof(upm_FrameHeader, stride) == 16, "upm_FrameHeader.stride offset");
UPM_STATIC_ASSERT(offsetof(upm_FrameHeader, reserved) == 20, "upm_FrameHeader.reserved offset");
UPM_STATIC_ASSERT(offsetof(upm_FrameHeader, seq) == 24, "upm_FrameHeader.seq offset");
UPM_STATIC_ASSERT(offsetof(upm_FrameHeader, stamp_ns) == 32, "upm_FrameHeader.stamp_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_FrameHeader, exposure_ns) == 40, "upm_FrameHeader.exposure_ns offset");

/* iceoryx2 type name "upm::DriverTelemetry.v6", 96 bytes, align 8 */
#define UPM_DRIVERTELEMETRY_TYPE_NAME "upm::DriverTelemetry.v6"
typedef struct {
    uint32_t kind;
    uint32_t state;
    uint64_t faults[8];
    uint64_t lost_frames;
    uint64_t bad_frames;
    int64_t sync0_phase_ns;
} upm_DriverTelemetry;
UPM_STATIC_ASSERT(sizeof(upm_DriverTelemetry) == 96, "upm_DriverTelemetry size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_DriverTelemetry) == 8, "upm_DriverTelemetry align");
UPM_STATIC_ASSERT(offsetof(upm_DriverTelemetry, kind) == 0, "upm_DriverTelemetry.kind offset");
UPM_STATIC_ASSERT(offsetof(upm_DriverTelemetry, state) == 4, "upm_DriverTelemetry.state offset");
UPM_STATIC_ASSERT(offsetof(upm_DriverTelemetry, faults) == 8, "upm_DriverTelemetry.faults offset");
UPM_STATIC_ASSERT(offsetof(upm_DriverTelemetry, lost_frames) == 72, "upm_DriverTelemetry.lost_frames offset");
UPM_STATIC_ASSERT(offsetof(upm_DriverTelemetry, bad_frames) == 80, "upm_DriverTelemetry.bad_frames offset");
UPM_STATIC_ASSERT(offsetof(upm_DriverTelemetry, sync0_phase_ns) == 88, "upm_DriverTelemetry.sync0_phase_ns offset");

/* iceoryx2 type name "upm::CoreCounters.v6", 96 bytes, align 8 */
#define UPM_CORECOUNTERS_TYPE_NAME "upm::CoreCounters.v6"
typedef struct {
    uint64_t ticks;
    uint64_t overruns;
    uint64_t hold_events;
    uint64_t schedule_swaps;
    uint64_t rejected_parts;
    uint64_t rejected_requests;
    uint64_t rt_thread_allocations;
    uint64_t driver_faults;
    uint64_t driver_clamped;
    uint64_t driver_rejected;
    uint64_t fault_holds;
    uint64_t resumes;
} upm_CoreCounters;
UPM_STATIC_ASSERT(sizeof(upm_CoreCounters) == 96, "upm_CoreCounters size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_CoreCounters) == 8, "upm_CoreCounters align");
UPM_STATIC_ASSERT(offsetof(upm_CoreCounters, ticks) == 0, "upm_CoreCounters.ticks offset");
UPM_STATIC_ASSERT(offsetof(upm_CoreCounters, overruns) == 8, "upm_CoreCounters.overruns offset");
UPM_STATIC_ASSERT(offsetof(upm_CoreCounters, hold_events) == 16, "upm_CoreCounters.hold_events offset");
UPM_STATIC_ASSERT(offsetof(upm_CoreCounters, schedule_swaps) == 24, "upm_CoreCounters.schedule_swaps offset");
UPM_STATIC_ASSERT(offsetof(upm_CoreCounters, rejected_parts) == 32, "upm_CoreCounters.rejected_parts offset");
UPM_STATIC_ASSERT(offsetof(upm_CoreCounters, rejected_requests) == 40, "upm_CoreCounters.rejected_requests offset");
UPM_STATIC_ASSERT(offsetof(upm_CoreCounters, rt_thread_allocations) == 48, "upm_CoreCounters.rt_thread_allocations offset");
UPM_STATIC_ASSERT(offsetof(upm_CoreCounters, driver_faults) == 56, "upm_CoreCounters.driver_faults offset");
UPM_STATIC_ASSERT(offsetof(upm_CoreCounters, driver_clamped) == 64, "upm_CoreCounters.driver_clamped offset");
UPM_STATIC_ASSERT(offsetof(upm_CoreCounters, driver_rejected) == 72, "upm_CoreCounters.driver_rejected offset");
UPM_STATIC_ASSERT(offsetof(upm_CoreCounters, fault_holds) == 80, "upm_CoreCounters.fault_holds offset");
UPM_STATIC_ASSERT(offsetof(upm_CoreCounters, resumes) == 88, "upm_CoreCounters.resumes offset");

/* iceoryx2 type name "upm::LatencyPercentiles.v6", 40 bytes, align 8 */
#define UPM_LATENCYPERCENTILES_TYPE_NAME "upm::LatencyPercentiles.v6"
typedef struct {
    uint64_t samples;
    uint64_t p50_ns;
    uint64_t p99_ns;
    uint64_t p999_ns;
    uint64_t max_ns;
} upm_LatencyPercentiles;
UPM_STATIC_ASSERT(sizeof(upm_LatencyPercentiles) == 40, "upm_LatencyPercentiles size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_LatencyPercentiles) == 8, "upm_LatencyPercentiles align");
UPM_STATIC_ASSERT(offsetof(upm_LatencyPercentiles, samples) == 0, "upm_LatencyPercentiles.samples offset");
UPM_STATIC_ASSERT(offsetof(upm_LatencyPercentiles, p50_ns) == 8, "upm_LatencyPercentiles.p50_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_LatencyPercentiles, p99_ns) == 16, "upm_LatencyPercentiles.p99_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_LatencyPercentiles, p999_ns) == 24, "upm_LatencyPercentiles.p999_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_LatencyPercentiles, max_ns) == 32, "upm_LatencyPercentiles.max_ns offset");

/* iceoryx2 type name "upm::CoreLatencies.v6", 160 bytes, align 8 */
#define UPM_CORELATENCIES_TYPE_NAME "upm::CoreLatencies.v6"
typedef struct {
    upm_LatencyPercentiles motor_wakeup;
    upm_LatencyPercentiles solver;
    upm_LatencyPercentiles ipc_vision_to_core;
    upm_LatencyPercentiles frame_to_schedule;
} upm_CoreLatencies;
UPM_STATIC_ASSERT(sizeof(upm_CoreLatencies) == 160, "upm_CoreLatencies size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_CoreLatencies) == 8, "upm_CoreLatencies align");
UPM_STATIC_ASSERT(offsetof(upm_CoreLatencies, motor_wakeup) == 0, "upm_CoreLatencies.motor_wakeup offset");
UPM_STATIC_ASSERT(offsetof(upm_CoreLatencies, solver) == 40, "upm_CoreLatencies.solver offset");
UPM_STATIC_ASSERT(offsetof(upm_CoreLatencies, ipc_vision_to_core) == 80, "upm_CoreLatencies.ipc_vision_to_core offset");
UPM_STATIC_ASSERT(offsetof(upm_CoreLatencies, frame_to_schedule) == 120, "upm_CoreLatencies.frame_to_schedule offset");

/* iceoryx2 type name "upm::Telemetry.v6", 840 bytes, align 8 */
#define UPM_TELEMETRY_TYPE_NAME "upm::Telemetry.v6"
typedef struct {
    uint32_t protocol_version;
    uint32_t state;
    uint64_t seq;
    uint64_t stamp_ns;
    uint64_t cycle;
    double plate_x;
    double plate_y;
    double plate_theta;
    upm_CoreCounters counters;
    double parts_age_ms;
    double request_age_ms;
    upm_CoreLatencies latency;
    uint32_t core_pid;
    uint32_t vision_pid;
    uint32_t planner_pid;
    uint32_t realtime_flags;
    uint64_t vision_started_ns;
    uint64_t planner_started_ns;
    uint64_t rejected_by_reason[32];
    uint32_t health_source;
    uint32_t health_cause;
    uint8_t health_detail[120];
    upm_DriverTelemetry driver;
} upm_Telemetry;
UPM_STATIC_ASSERT(sizeof(upm_Telemetry) == 840, "upm_Telemetry size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_Telemetry) == 8, "upm_Telemetry align");
UPM_STATIC_ASSERT(offsetof(upm_Telemetry, protocol_version) == 0, "upm_Telemetry.protocol_version offset");
UPM_STATIC_ASSERT(offsetof(upm_Telemetry, state) == 4, "upm_Telemetry.state offset");
UPM_STATIC_ASSERT(offsetof(upm_Telemetry, seq) == 8, "upm_Telemetry.seq offset");
UPM_STATIC_ASSERT(offsetof(upm_Telemetry, stamp_ns) == 16, "upm_Telemetry.stamp_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_Telemetry, cycle) == 24, "upm_Telemetry.cycle offset");
UPM_STATIC_ASSERT(offsetof(upm_Telemetry, plate_x) == 32, "upm_Telemetry.plate_x offset");
UPM_STATIC_ASSERT(offsetof(upm_Telemetry, plate_y) == 40, "upm_Telemetry.plate_y offset");
UPM_STATIC_ASSERT(offsetof(upm_Telemetry, plate_theta) == 48, "upm_Telemetry.plate_theta offset");
UPM_STATIC_ASSERT(offsetof(upm_Telemetry, counters) == 56, "upm_Telemetry.counters offset");
UPM_STATIC_ASSERT(offsetof(upm_Telemetry, parts_age_ms) == 152, "upm_Telemetry.parts_age_ms offset");
UPM_STATIC_ASSERT(offsetof(upm_Telemetry, request_age_ms) == 160, "upm_Telemetry.request_age_ms offset");
UPM_STATIC_ASSERT(offsetof(upm_Telemetry, latency) == 168, "upm_Telemetry.latency offset");
UPM_STATIC_ASSERT(offsetof(upm_Telemetry, core_pid) == 328, "upm_Telemetry.core_pid offset");
UPM_STATIC_ASSERT(offsetof(upm_Telemetry, vision_pid) == 332, "upm_Telemetry.vision_pid offset");
UPM_STATIC_ASSERT(offsetof(upm_Telemetry, planner_pid) == 336, "upm_Telemetry.planner_pid offset");
UPM_STATIC_ASSERT(offsetof(upm_Telemetry, realtime_flags) == 340, "upm_Telemetry.realtime_flags offset");
UPM_STATIC_ASSERT(offsetof(upm_Telemetry, vision_started_ns) == 344, "upm_Telemetry.vision_started_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_Telemetry, planner_started_ns) == 352, "upm_Telemetry.planner_started_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_Telemetry, rejected_by_reason) == 360, "upm_Telemetry.rejected_by_reason offset");
UPM_STATIC_ASSERT(offsetof(upm_Telemetry, health_source) == 616, "upm_Telemetry.health_source offset");
UPM_STATIC_ASSERT(offsetof(upm_Telemetry, health_cause) == 620, "upm_Telemetry.health_cause offset");
UPM_STATIC_ASSERT(offsetof(upm_Telemetry, health_detail) == 624, "upm_Telemetry.health_detail offset");
UPM_STATIC_ASSERT(offsetof(upm_Telemetry, driver) == 744, "upm_Telemetry.driver offset");

/* iceoryx2 type name "upm::PickEvent.v6", 56 bytes, align 8 */
#define UPM_PICKEVENT_TYPE_NAME "upm::PickEvent.v6"
typedef struct {
    uint64_t number;
    uint32_t part_id;
    uint32_t class_;
    uint32_t pose;
    uint32_t reserved;
    double time_s;
    double position_error_m;
    double angle_error_rad;
    double on_plate_s;
} upm_PickEvent;
UPM_STATIC_ASSERT(sizeof(upm_PickEvent) == 56, "upm_PickEvent size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_PickEvent) == 8, "upm_PickEvent align");
UPM_STATIC_ASSERT(offsetof(upm_PickEvent, number) == 0, "upm_PickEvent.number offset");
UPM_STATIC_ASSERT(offsetof(upm_PickEvent, part_id) == 8, "upm_PickEvent.part_id offset");
UPM_STATIC_ASSERT(offsetof(upm_PickEvent, class_) == 12, "upm_PickEvent.class_ offset");
UPM_STATIC_ASSERT(offsetof(upm_PickEvent, pose) == 16, "upm_PickEvent.pose offset");
UPM_STATIC_ASSERT(offsetof(upm_PickEvent, reserved) == 20, "upm_PickEvent.reserved offset");
UPM_STATIC_ASSERT(offsetof(upm_PickEvent, time_s) == 24, "upm_PickEvent.time_s offset");
UPM_STATIC_ASSERT(offsetof(upm_PickEvent, position_error_m) == 32, "upm_PickEvent.position_error_m offset");
UPM_STATIC_ASSERT(offsetof(upm_PickEvent, angle_error_rad) == 40, "upm_PickEvent.angle_error_rad offset");
UPM_STATIC_ASSERT(offsetof(upm_PickEvent, on_plate_s) == 48, "upm_PickEvent.on_plate_s offset");

/* iceoryx2 type name "upm::PickPoseState.v6", 40 bytes, align 8 */
#define UPM_PICKPOSESTATE_TYPE_NAME "upm::PickPoseState.v6"
typedef struct {
    uint32_t class_;
    uint32_t part_id;
    uint32_t ready;
    uint32_t reserved;
    double x;
    double y;
    double theta;
} upm_PickPoseState;
UPM_STATIC_ASSERT(sizeof(upm_PickPoseState) == 40, "upm_PickPoseState size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_PickPoseState) == 8, "upm_PickPoseState align");
UPM_STATIC_ASSERT(offsetof(upm_PickPoseState, class_) == 0, "upm_PickPoseState.class_ offset");
UPM_STATIC_ASSERT(offsetof(upm_PickPoseState, part_id) == 4, "upm_PickPoseState.part_id offset");
UPM_STATIC_ASSERT(offsetof(upm_PickPoseState, ready) == 8, "upm_PickPoseState.ready offset");
UPM_STATIC_ASSERT(offsetof(upm_PickPoseState, reserved) == 12, "upm_PickPoseState.reserved offset");
UPM_STATIC_ASSERT(offsetof(upm_PickPoseState, x) == 16, "upm_PickPoseState.x offset");
UPM_STATIC_ASSERT(offsetof(upm_PickPoseState, y) == 24, "upm_PickPoseState.y offset");
UPM_STATIC_ASSERT(offsetof(upm_PickPoseState, theta) == 32, "upm_PickPoseState.theta offset");

/* iceoryx2 type name "upm::FeedStatus.v6", 1632 bytes, align 8 */
#define UPM_FEEDSTATUS_TYPE_NAME "upm::FeedStatus.v6"
typedef struct {
    uint32_t protocol_version;
    uint32_t count;
    uint64_t seq;
    uint64_t stamp_ns;
    uint64_t arrived;
    uint64_t picked;
    uint64_t lost;
    uint64_t arrivals_blocked;
    uint32_t on_plate;
    uint32_t stuck;
    uint32_t recent_count;
    uint32_t collisions;
    double time_s;
    double robot_busy_s;
    double stuck_after_s;
    upm_PickEvent recent[16];
    upm_PickPoseState poses[16];
} upm_FeedStatus;
UPM_STATIC_ASSERT(sizeof(upm_FeedStatus) == 1632, "upm_FeedStatus size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_FeedStatus) == 8, "upm_FeedStatus align");
UPM_STATIC_ASSERT(offsetof(upm_FeedStatus, protocol_version) == 0, "upm_FeedStatus.protocol_version offset");
UPM_STATIC_ASSERT(offsetof(upm_FeedStatus, count) == 4, "upm_FeedStatus.count offset");
UPM_STATIC_ASSERT(offsetof(upm_FeedStatus, seq) == 8, "upm_FeedStatus.seq offset");
UPM_STATIC_ASSERT(offsetof(upm_FeedStatus, stamp_ns) == 16, "upm_FeedStatus.stamp_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_FeedStatus, arrived) == 24, "upm_FeedStatus.arrived offset");
UPM_STATIC_ASSERT(offsetof(upm_FeedStatus, picked) == 32, "upm_FeedStatus.picked offset");
UPM_STATIC_ASSERT(offsetof(upm_FeedStatus, lost) == 40, "upm_FeedStatus.lost offset");
UPM_STATIC_ASSERT(offsetof(upm_FeedStatus, arrivals_blocked) == 48, "upm_FeedStatus.arrivals_blocked offset");
UPM_STATIC_ASSERT(offsetof(upm_FeedStatus, on_plate) == 56, "upm_FeedStatus.on_plate offset");
UPM_STATIC_ASSERT(offsetof(upm_FeedStatus, stuck) == 60, "upm_FeedStatus.stuck offset");
UPM_STATIC_ASSERT(offsetof(upm_FeedStatus, recent_count) == 64, "upm_FeedStatus.recent_count offset");
UPM_STATIC_ASSERT(offsetof(upm_FeedStatus, collisions) == 68, "upm_FeedStatus.collisions offset");
UPM_STATIC_ASSERT(offsetof(upm_FeedStatus, time_s) == 72, "upm_FeedStatus.time_s offset");
UPM_STATIC_ASSERT(offsetof(upm_FeedStatus, robot_busy_s) == 80, "upm_FeedStatus.robot_busy_s offset");
UPM_STATIC_ASSERT(offsetof(upm_FeedStatus, stuck_after_s) == 88, "upm_FeedStatus.stuck_after_s offset");
UPM_STATIC_ASSERT(offsetof(upm_FeedStatus, recent) == 96, "upm_FeedStatus.recent offset");
UPM_STATIC_ASSERT(offsetof(upm_FeedStatus, poses) == 992, "upm_FeedStatus.poses offset");

/* iceoryx2 type name "upm::PickCommand.v6", 32 bytes, align 8 */
#define UPM_PICKCOMMAND_TYPE_NAME "upm::PickCommand.v6"
typedef struct {
    uint32_t protocol_version;
    uint32_t pose;
    uint64_t seq;
    uint64_t stamp_ns;
    uint32_t part_id;
    uint32_t reserved;
} upm_PickCommand;
UPM_STATIC_ASSERT(sizeof(upm_PickCommand) == 32, "upm_PickCommand size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_PickCommand) == 8, "upm_PickCommand align");
UPM_STATIC_ASSERT(offsetof(upm_PickCommand, protocol_version) == 0, "upm_PickCommand.protocol_version offset");
UPM_STATIC_ASSERT(offsetof(upm_PickCommand, pose) == 4, "upm_PickCommand.pose offset");
UPM_STATIC_ASSERT(offsetof(upm_PickCommand, seq) == 8, "upm_PickCommand.seq offset");
UPM_STATIC_ASSERT(offsetof(upm_PickCommand, stamp_ns) == 16, "upm_PickCommand.stamp_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_PickCommand, part_id) == 24, "upm_PickCommand.part_id offset");
UPM_STATIC_ASSERT(offsetof(upm_PickCommand, reserved) == 28, "upm_PickCommand.reserved offset");

/* iceoryx2 type name "upm::RecipeCommand.v6", 264 bytes, align 8 */
#define UPM_RECIPECOMMAND_TYPE_NAME "upm::RecipeCommand.v6"
typedef struct {
    uint32_t protocol_version;
    uint32_t path_len;
    uint64_t seq;
    uint64_t stamp_ns;
    uint8_t path[240];
} upm_RecipeCommand;
UPM_STATIC_ASSERT(sizeof(upm_RecipeCommand) == 264, "upm_RecipeCommand size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_RecipeCommand) == 8, "upm_RecipeCommand align");
UPM_STATIC_ASSERT(offsetof(upm_RecipeCommand, protocol_version) == 0, "upm_RecipeCommand.protocol_version offset");
UPM_STATIC_ASSERT(offsetof(upm_RecipeCommand, path_len) == 4, "upm_RecipeCommand.path_len offset");
UPM_STATIC_ASSERT(offsetof(upm_RecipeCommand, seq) == 8, "upm_RecipeCommand.seq offset");
UPM_STATIC_ASSERT(offsetof(upm_RecipeCommand, stamp_ns) == 16, "upm_RecipeCommand.stamp_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_RecipeCommand, path) == 24, "upm_RecipeCommand.path offset");

/* iceoryx2 type name "upm::LineStatus.v6", 120 bytes, align 8 */
#define UPM_LINESTATUS_TYPE_NAME "upm::LineStatus.v6"
typedef struct {
    uint32_t protocol_version;
    uint32_t line_pid;
    uint64_t seq;
    uint64_t stamp_ns;
    uint32_t opcua_sessions;
    uint32_t modbus_connections;
    uint64_t login_failures;
    uint64_t access_denied;
    uint64_t bad_arguments;
    uint64_t invalid_state;
    uint64_t failed_calls;
    uint64_t modbus_exceptions;
    uint64_t modbus_bad_frames;
    uint64_t modbus_refused_connections;
    uint64_t picks_sent;
    uint64_t recipes_loaded;
    uint64_t recipes_refused;
} upm_LineStatus;
UPM_STATIC_ASSERT(sizeof(upm_LineStatus) == 120, "upm_LineStatus size");
UPM_STATIC_ASSERT(UPM_ALIGNOF(upm_LineStatus) == 8, "upm_LineStatus align");
UPM_STATIC_ASSERT(offsetof(upm_LineStatus, protocol_version) == 0, "upm_LineStatus.protocol_version offset");
UPM_STATIC_ASSERT(offsetof(upm_LineStatus, line_pid) == 4, "upm_LineStatus.line_pid offset");
UPM_STATIC_ASSERT(offsetof(upm_LineStatus, seq) == 8, "upm_LineStatus.seq offset");
UPM_STATIC_ASSERT(offsetof(upm_LineStatus, stamp_ns) == 16, "upm_LineStatus.stamp_ns offset");
UPM_STATIC_ASSERT(offsetof(upm_LineStatus, opcua_sessions) == 24, "upm_LineStatus.opcua_sessions offset");
UPM_STATIC_ASSERT(offsetof(upm_LineStatus, modbus_connections) == 28, "upm_LineStatus.modbus_connections offset");
UPM_STATIC_ASSERT(offsetof(upm_LineStatus, login_failures) == 32, "upm_LineStatus.login_failures offset");
UPM_STATIC_ASSERT(offsetof(upm_LineStatus, access_denied) == 40, "upm_LineStatus.access_denied offset");
UPM_STATIC_ASSERT(offsetof(upm_LineStatus, bad_arguments) == 48, "upm_LineStatus.bad_arguments offset");
UPM_STATIC_ASSERT(offsetof(upm_LineStatus, invalid_state) == 56, "upm_LineStatus.invalid_state offset");
UPM_STATIC_ASSERT(offsetof(upm_LineStatus, failed_calls) == 64, "upm_LineStatus.failed_calls offset");
UPM_STATIC_ASSERT(offsetof(upm_LineStatus, modbus_exceptions) == 72, "upm_LineStatus.modbus_exceptions offset");
UPM_STATIC_ASSERT(offsetof(upm_LineStatus, modbus_bad_frames) == 80, "upm_LineStatus.modbus_bad_frames offset");
UPM_STATIC_ASSERT(offsetof(upm_LineStatus, modbus_refused_connections) == 88, "upm_LineStatus.modbus_refused_connections offset");
UPM_STATIC_ASSERT(offsetof(upm_LineStatus, picks_sent) == 96, "upm_LineStatus.picks_sent offset");
UPM_STATIC_ASSERT(offsetof(upm_LineStatus, recipes_loaded) == 104, "upm_LineStatus.recipes_loaded offset");
UPM_STATIC_ASSERT(offsetof(upm_LineStatus, recipes_refused) == 112, "upm_LineStatus.recipes_refused offset");

#endif /* UPM_MESSAGES_H */
