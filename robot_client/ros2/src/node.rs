//! The node on DDS: one task per input topic, the latest sensor data kept for the next click,
//! clicks and inventory rounds answered, trials recorded. Everything it computes is done by
//! [`crate::click`] and [`crate::registry_bridge`]; this file only moves messages.

use std::sync::{Arc, Mutex};

use pps_robot::navigation::ApproachParams;
use pps_robot::perception::{DepthNoise, TagSearchParams};
use pps_robot::registry::RegistryClient;
use pps_robot::task::{ColourSource, search_for_known_tags, search_in_the_registered_colour};
use pps_schema::Epc;
use ros2_client::{Context, NodeName, NodeOptions, Publisher};
use time::OffsetDateTime;

use crate::click::RangeInput;
use crate::click::{SensorState, answer_click};
use crate::cloud::point_cloud;
use crate::depth::depth_frame;
use crate::input_error::InputError;
use crate::msg::geometry::{PointStamped, PoseStamped};
use crate::msg::pps::{TagEntry, TagReads, Trial};
use crate::msg::sensor::{CameraInfo, Image, PointCloud2};
use crate::msg::tf::TfMessage;
use crate::msg::visualization::{HumbleMarkerArray, MarkerArray, MarkerLayout};
use crate::once::LogOnce;
use crate::picture::{LastView, PerceivedView};
use crate::qos;
use crate::registry_bridge::{entry_for_round, hal_reads, record_trial, trial_document};
use crate::topics::{Topics, advertise, subscribe};

/// How the node is set up.
#[derive(Debug, Clone)]
pub struct NodeSettings {
    pub topics: Topics,
    /// The frame the cloud and the click are in, and the goal is given in.
    pub base_frame: String,
    pub approach: ApproachParams,
    /// The range sensor's noise as stated; when not, a depth camera's or a laser's by what the
    /// range data came as.
    pub depth_noise: Option<DepthNoise>,
    /// Two tags closer than this in RSSI are ambiguous, dB.
    pub rfid_margin_db: f64,
    /// The layout of the markers the robot's RViz reads.
    pub marker_layout: MarkerLayout,
    /// Send each trial with the picture of the click that led to it.
    pub picture: bool,
    /// Look for the colour the home's tags have (learned or in their entries), or for the one
    /// given.
    pub colour: ColourSource,
}

/// `/pps/markers` in the layout the robot's ROS 2 distribution reads.
enum MarkerPublisher {
    Iron(Publisher<MarkerArray>),
    Humble(Publisher<HumbleMarkerArray>),
}

impl MarkerPublisher {
    fn publish(&self, topic: &str, markers: MarkerArray) {
        match self {
            Self::Iron(publisher) => publish(publisher, topic, markers),
            Self::Humble(publisher) => publish(publisher, topic, HumbleMarkerArray::from(markers)),
        }
    }
}

/// The node's outputs.
struct Outputs {
    tag_pose: Publisher<PoseStamped>,
    goal_pose: Publisher<PoseStamped>,
    markers: MarkerPublisher,
    entry: Publisher<TagEntry>,
}

/// What every task shares.
struct Shared {
    settings: NodeSettings,
    sensors: Mutex<SensorState>,
    once: LogOnce,
    outputs: Outputs,
    registry: RegistryClient,
    last_view: LastView,
    /// What the last click's tag search was told of the home's tags, said again only when it
    /// changes.
    known_tags: Mutex<Vec<String>>,
}

/// Logs a message that could not be published; a full queue or a vanished reader is the
/// readers' trouble, never a reason to stop.
fn publish<M: serde::Serialize>(publisher: &Publisher<M>, topic: &str, message: M) {
    if let Err(e) = publisher.publish(message) {
        tracing::warn!(topic, "could not publish: {e}");
    }
}

/// Runs the node until `shutdown` resolves.
pub async fn run(
    context: Context,
    registry: RegistryClient,
    settings: NodeSettings,
    shutdown: impl std::future::Future<Output = ()>,
) -> anyhow::Result<()> {
    let name = NodeName::new("/", "pps_ros2").map_err(|e| anyhow::anyhow!("{e}"))?;
    let mut node = context
        .new_node(name, NodeOptions::new().enable_rosout(false))
        .map_err(|e| anyhow::anyhow!("cannot create the ROS 2 node: {e:?}"))?;
    let topics = settings.topics.clone();
    let image = subscribe::<Image>(&mut node, &topics.image, qos::sensor_stream())?;
    let camera_info =
        subscribe::<CameraInfo>(&mut node, &topics.camera_info, qos::sensor_stream())?;
    let points = subscribe::<PointCloud2>(&mut node, &topics.points, qos::sensor_stream())?;
    let depth = subscribe::<Image>(&mut node, &topics.depth, qos::sensor_stream())?;
    let depth_info = subscribe::<CameraInfo>(&mut node, &topics.depth_info, qos::sensor_stream())?;
    let tf_static = subscribe::<TfMessage>(&mut node, &topics.tf_static, qos::latched())?;
    let clicks = subscribe::<PointStamped>(&mut node, &topics.clicked_point, qos::command())?;
    let rounds = subscribe::<TagReads>(&mut node, &topics.rfid, qos::command())?;
    let trials = subscribe::<Trial>(&mut node, &topics.trial, qos::command())?;
    let outputs = Outputs {
        tag_pose: advertise(&mut node, &topics.tag_pose, qos::command())?,
        goal_pose: advertise(&mut node, &topics.goal_pose, qos::command())?,
        markers: match settings.marker_layout {
            MarkerLayout::Iron => {
                MarkerPublisher::Iron(advertise(&mut node, &topics.markers, qos::command())?)
            }
            MarkerLayout::Humble => {
                MarkerPublisher::Humble(advertise(&mut node, &topics.markers, qos::command())?)
            }
        },
        entry: advertise(&mut node, &topics.entry, qos::command())?,
    };
    let spinner = node.spinner().map_err(|e| anyhow::anyhow!("cannot spin the node: {e:?}"))?;
    let shared = Arc::new(Shared {
        settings,
        sensors: Mutex::new(SensorState::default()),
        once: LogOnce::default(),
        outputs,
        registry,
        last_view: LastView::default(),
        known_tags: Mutex::default(),
    });
    tracing::info!(
        base_frame = %shared.settings.base_frame,
        "pps-ros2 is up: waiting for {}, {} or {} with {}, and clicks on {}",
        [&topics.image, &topics.camera_info, &topics.tf_static].map(|t| t.as_str()).join(", "),
        topics.points,
        topics.depth,
        topics.depth_info,
        topics.clicked_point
    );
    let mut tasks = tokio::task::JoinSet::new();
    tasks.spawn(async move {
        if let Err(e) = spinner.spin().await {
            tracing::error!("the ROS 2 node stopped spinning: {e:?}");
        }
    });
    macro_rules! each_message {
        ($subscription:ident, $topic:expr, $handle:expr) => {{
            let shared = shared.clone();
            tasks.spawn(async move {
                loop {
                    match $subscription.async_take().await {
                        Ok((message, _)) => $handle(&shared, message).await,
                        Err(e) => tracing::warn!(topic = %$topic, "a message could not be read: {e}"),
                    }
                }
            });
        }};
    }
    each_message!(image, topics.image, on_image);
    each_message!(camera_info, topics.camera_info, on_camera_info);
    each_message!(points, topics.points, on_points);
    each_message!(depth, topics.depth, on_depth);
    each_message!(depth_info, topics.depth_info, on_depth_info);
    each_message!(tf_static, topics.tf_static, on_tf_static);
    each_message!(clicks, topics.clicked_point, on_click);
    each_message!(rounds, topics.rfid, on_round);
    each_message!(trials, topics.trial, on_trial);
    tasks.spawn(flush_outbox_now_and_then(shared.clone()));
    shutdown.await;
    tasks.abort_all();
    Ok(())
}

async fn on_image(shared: &Arc<Shared>, image: Image) {
    let mut sensors = shared.sensors.lock().unwrap_or_else(|e| e.into_inner());
    sensors.image = Some(Arc::new(image));
}

async fn on_camera_info(shared: &Arc<Shared>, info: CameraInfo) {
    let mut sensors = shared.sensors.lock().unwrap_or_else(|e| e.into_inner());
    sensors.camera_info = Some(Arc::new(info));
}

async fn on_points(shared: &Arc<Shared>, cloud: PointCloud2) {
    const TOPIC: &str = "points";
    let base = &shared.settings.base_frame;
    let frame = cloud.header.frame_id.trim_start_matches('/');
    let read = if frame.is_empty() || frame == base {
        point_cloud(&cloud)
    } else {
        Err(InputError::CloudFrame { got: frame.to_owned(), base: base.clone() })
    };
    match read {
        Ok(points) => {
            let cloud = RangeInput::Cloud(Arc::new(points));
            shared.sensors.lock().unwrap_or_else(|e| e.into_inner()).range = Some(cloud);
            shared.once.recovered(TOPIC);
        }
        Err(error) => {
            shared.once.warn(TOPIC, &error);
        }
    }
}

async fn on_depth(shared: &Arc<Shared>, image: Image) {
    const TOPIC: &str = "depth";
    match depth_frame(image) {
        Ok(frame) => {
            let depth = RangeInput::Depth(Arc::new(frame));
            shared.sensors.lock().unwrap_or_else(|e| e.into_inner()).range = Some(depth);
            shared.once.recovered(TOPIC);
        }
        Err(error) => {
            shared.once.warn(TOPIC, &error);
        }
    }
}

async fn on_depth_info(shared: &Arc<Shared>, info: CameraInfo) {
    let mut sensors = shared.sensors.lock().unwrap_or_else(|e| e.into_inner());
    sensors.depth_info = Some(Arc::new(info));
}

async fn on_tf_static(shared: &Arc<Shared>, message: TfMessage) {
    let unusable =
        shared.sensors.lock().unwrap_or_else(|e| e.into_inner()).transforms.insert(&message);
    for reason in unusable {
        tracing::warn!(topic = "tf_static", "{reason} (ignored)");
    }
}

async fn on_click(shared: &Arc<Shared>, click: PointStamped) {
    const TOPIC: &str = "clicked_point";
    let snapshot = shared.sensors.lock().unwrap_or_else(|e| e.into_inner()).clone();
    shared.registry.refresh_announced().await;
    let (approach, registered) = approach_for_known_tags(shared);
    let work = shared.clone();
    // The chain takes tens of milliseconds of computation: off the tasks that move messages.
    let answered = tokio::task::spawn_blocking(move || {
        let settings = &work.settings;
        let answer = |approach: &ApproachParams| {
            answer_click(&snapshot, &click, &settings.base_frame, approach, settings.depth_noise)
        };
        let first = answer(&approach)?;
        match registered {
            Some((tag, note)) if first.plan.saw_nothing_red() => {
                tracing::info!("tag search: {note}");
                answer(&ApproachParams { tag, ..approach })
            }
            _ => Ok(first),
        }
    })
    .await;
    let answer = match answered {
        Ok(Ok(answer)) => {
            shared.once.recovered(TOPIC);
            answer
        }
        Ok(Err(error)) => {
            shared.once.warn(TOPIC, &error);
            return;
        }
        Err(e) => {
            tracing::error!("perception failed on this click: {e}");
            return;
        }
    };
    let topics = &shared.settings.topics;
    let outputs = &shared.outputs;
    outputs.markers.publish(&topics.markers, answer.markers);
    // Kept also without pictures: the next trial's tag colour is measured in it.
    shared.last_view.perceived(PerceivedView {
        image: answer.image,
        calibration: answer.calibration,
        plan: answer.plan,
        at: OffsetDateTime::now_utc(),
        read: None,
    });
    match (answer.tag_pose, answer.goal_pose) {
        (Some(tag), Some(goal)) => {
            tracing::info!(
                "tag at ({:.3}, {:.3}, {:.3}); goal ({:.3}, {:.3})",
                tag.pose.position.x,
                tag.pose.position.y,
                tag.pose.position.z,
                goal.pose.position.x,
                goal.pose.position.y
            );
            publish(&outputs.tag_pose, &topics.tag_pose, tag);
            publish(&outputs.goal_pose, &topics.goal_pose, goal);
        }
        (Some(tag), None) => {
            tracing::info!("a tag was found but no surface behind it to approach along");
            publish(&outputs.tag_pose, &topics.tag_pose, tag);
        }
        _ => tracing::info!("no tag near the clicked point"),
    }
}

/// The approach's settings with the tag search set for the home's tags as the registry's
/// entries (cached, so also offline) know them now; what changed since the last click is logged.
/// Beside them, the search in the registered colour to look again with when the household's
/// learned colour sees nothing red ([`search_in_the_registered_colour`]).
fn approach_for_known_tags(shared: &Shared) -> (ApproachParams, Option<(TagSearchParams, String)>) {
    let settings = &shared.settings;
    let known = shared.registry.known_entries();
    let (tag, notes) = search_for_known_tags(&settings.approach.tag, &known, settings.colour);
    let registered = search_in_the_registered_colour(&tag, &known);
    let mut said = shared.known_tags.lock().unwrap_or_else(|e| e.into_inner());
    if *said != notes {
        for note in &notes {
            tracing::info!("tag search: {note}");
        }
        *said = notes;
    }
    (ApproachParams { tag, ..settings.approach.clone() }, registered)
}

async fn on_round(shared: &Arc<Shared>, round: TagReads) {
    const TOPIC: &str = "rfid";
    let (_, refused) = hal_reads(&round);
    match refused.into_iter().next() {
        Some(reason) => {
            shared.once.warn(TOPIC, &InputError::TagRead(reason));
        }
        None => shared.once.recovered(TOPIC),
    }
    let entry = entry_for_round(&shared.registry, &round, shared.settings.rfid_margin_db).await;
    // A round in which tags answered says which the fingers are on, if any one; a round in
    // which none did says nothing.
    if let Ok(epc) = Epc::parse(&entry.epc) {
        shared.last_view.read((!entry.ambiguous).then_some(epc));
    }
    if !entry.error.is_empty() {
        tracing::info!("inventory round: {}", entry.error);
    }
    publish(&shared.outputs.entry, &shared.settings.topics.entry, entry);
}

async fn on_trial(shared: &Arc<Shared>, message: Trial) {
    let mut trial = match trial_document(&shared.registry, &message) {
        Ok(trial) => trial,
        Err(e) => {
            tracing::warn!(topic = "trial", "{e} (ignored)");
            return;
        }
    };
    let (picture, (tag_color, tag_size)) = match shared.last_view.take_for(&trial) {
        Some(view) => {
            let settings = &shared.settings;
            let (footprint, search, draw) =
                (settings.approach.footprint, settings.approach.tag.clone(), settings.picture);
            let for_trial = trial.clone();
            // Drawing, encoding and the colour's statistics take milliseconds: off the tasks
            // that move messages.
            let made = tokio::task::spawn_blocking(move || {
                let picture = if draw { view.picture(&footprint) } else { None };
                (picture, (view.tag_color(&for_trial, &search), view.tag_size(&for_trial, &search)))
            });
            made.await.unwrap_or_default()
        }
        None => (None, (None, None)),
    };
    // A colour or size the trial's sender measured itself is its own to give.
    let coloured = trial.tag_color.is_none() && tag_color.is_some();
    if coloured {
        trial.tag_color = tag_color;
    }
    let sized = trial.tag_size.is_none() && tag_size.is_some();
    if sized {
        trial.tag_size = tag_size;
    }
    let sent = [
        (picture.is_some(), "its picture"),
        (coloured, "its tag's colour"),
        (sized, "its tag's size"),
    ];
    let named: Vec<&str> = sent.iter().filter(|(sent, _)| *sent).map(|(_, what)| *what).collect();
    let with =
        if named.is_empty() { String::new() } else { format!(" with {}", named.join(" and ")) };
    match record_trial(&shared.registry, &trial, picture.as_deref()).await {
        Ok((id, report)) if report.remaining > 0 => tracing::info!(
            "trial {id} kept in the outbox; {} waiting for the registry",
            report.remaining
        ),
        Ok((id, report)) if report.rejected > 0 => {
            tracing::warn!("trial {id}: the registry refused it; set aside in the outbox")
        }
        Ok((id, _)) => tracing::info!("trial {id} recorded{with}"),
        Err(e) => tracing::warn!(topic = "trial", "{e} (ignored)"),
    }
}

/// Trials kept while the registry was away go up once it is back, without waiting for the
/// next trial.
async fn flush_outbox_now_and_then(shared: Arc<Shared>) {
    let mut every = tokio::time::interval(std::time::Duration::from_secs(5));
    loop {
        every.tick().await;
        match shared.registry.flush().await {
            Ok(report) if report.uploaded > 0 => {
                tracing::info!("{} waiting trials recorded", report.uploaded)
            }
            Ok(_) => {}
            Err(e) => tracing::warn!("the trial outbox could not be emptied: {e}"),
        }
    }
}
