//! rmf_dispenser_msgs (rmf_internal_msgs 4.1.0): definitions only. Its types have the fields of
//! rmf_ingestor_msgs' types, so the runtime has one type for both (`ItemType`,
//! `WorkcellRequest`, `WorkcellResult`, `WorkcellState`) and the topic names the ROS type
//! (`topics::ros_type`).

use super::Definition;

pub(crate) const REQUEST_ITEM: Definition = (
    "rmf_dispenser_msgs/msg/DispenserRequestItem",
    "string type_guid\nint32 quantity\nstring compartment_name\n",
);

pub(crate) const REQUEST: Definition = (
    "rmf_dispenser_msgs/msg/DispenserRequest",
    "builtin_interfaces/Time time\nstring request_guid\nstring target_guid\nstring transporter_type\nrmf_dispenser_msgs/DispenserRequestItem[] items\n",
);

pub(crate) const RESULT: Definition = (
    "rmf_dispenser_msgs/msg/DispenserResult",
    "builtin_interfaces/Time time\nstring request_guid\nstring source_guid\nuint8 status\n",
);

pub(crate) const STATE: Definition = (
    "rmf_dispenser_msgs/msg/DispenserState",
    "builtin_interfaces/Time time\nstring guid\nint32 mode\nstring[] request_guid_queue\nfloat32 seconds_remaining\n",
);
