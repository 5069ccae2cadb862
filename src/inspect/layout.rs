//! The recordings' layouts (Rerun blueprints), written here rather than with the SDK's builder.
//!
//! The `rerun` crate's blueprint builder (0.36.3) cannot set a view's properties: a time-series
//! view's x range ([`TimeAxis`]) and legend ([`PlotLegend`]), a 3D view's camera
//! ([`EyeControls3D`]), a 2D view's visible bounds ([`VisualBounds2D`]). Without an x range a
//! time-series view on a sequence timeline (a lateral offset in µm, a distance in mm) opens on a
//! small window around the time cursor — a sliver of the figure — and a 3D view's camera starts
//! wherever the viewer guesses. The blueprint is data like any other (archetypes logged to a
//! blueprint store, then activated), so this module logs it itself, with the same archetypes the
//! SDK's builder and Rerun's Python API log:
//!
//! | blueprint entity | archetype | what |
//! |---|---|---|
//! | `container/ID` | `ContainerBlueprint` | a horizontal, vertical, grid or tab container, its shares |
//! | `view/ID`, `view/ID/ViewContents` | `ViewBlueprint`, `ViewContents` | a view: class, title, origin, query |
//! | `view/ID/TimeAxis`, `…/ScalarAxis`, `…/PlotLegend`, `…/EyeControls3D`, `…/VisualBounds2D` | the properties | what a view opens on |
//! | `viewport`, `time_panel`, `blueprint_panel`, `selection_panel` | | the root container, the panels |
//!
//! **Every time-series view opens on its whole data**: its x range is the whole timeline
//! ([`TimeRange::EVERYTHING`], checked by screenshots: the view spans its data, not the cursor's
//! neighbourhood) unless one is given. The side panels and the time panel start collapsed (the
//! time panel to its bar: play, the cursor, the choice of timeline) so that the views get the
//! screen; a click opens them.
//!
//! A layout can be changed after it was sent ([`SentLayout::reorder`]): the run's recording puts
//! the worst wheelset's tab first once the run has found it.

use rerun::datatypes::Uuid;
use rerun::external::re_log_types::{BlueprintActivationCommand, LogMsg, RecordingId};
use rerun::external::re_sdk_types::blueprint::archetypes::{
    ContainerBlueprint, EyeControls3D, PanelBlueprint, PlotLegend, ScalarAxis, TimeAxis, TimePanelBlueprint,
    ViewBlueprint, ViewContents, ViewportBlueprint, VisualBounds2D,
};
use rerun::external::re_sdk_types::blueprint::components::{
    ActiveTab, ColumnShare, ContainerKind, Corner2D, Eye3DKind, GridColumns, IncludedContent, PanelState,
    QueryExpression, RootContainer, RowShare, TimelineName, ViewClass,
};
use rerun::external::re_sdk_types::components::{Name, Visible};
use rerun::external::re_sdk_types::datatypes::{
    Float32, Range1D, Range2D, TimeInt, TimeRange, TimeRangeBoundary,
};
use rerun::{AsComponents, RecordingStream, RecordingStreamResult, SerializedComponentBatch};

pub use rerun::external::re_sdk_types::blueprint::components::{Corner2D as Corner, PlayState};

/// A fresh blueprint id (`view/ID`, `container/ID`): a random UUID, as the viewer expects.
fn new_id() -> Uuid {
    Uuid::random()
}

/// A y range for data spanning `lo..=hi` whose axis is labelled at three round values at least:
/// the viewer labels its axes at powers of ten, and a range holding a single multiple of its
/// decade step shows a single label (`0` on a ±7.5 mm plot). The data padded by 5 %, widened
/// where needed to three multiples of its decade step D = 10^⌊log₁₀ span⌋, padded again by 3 %
/// so that those labels sit inside (a flat series: ± 1 % of its value, or ± 1 at zero); None for
/// no finite data.
pub fn round_range(lo: f64, hi: f64) -> Option<[f64; 2]> {
    if !(lo.is_finite() && hi.is_finite()) || lo > hi {
        return None;
    }
    let (lo, hi) = if hi > lo {
        (lo, hi)
    } else {
        let pad = if lo == 0.0 { 1.0 } else { 0.01 * lo.abs() };
        (lo - pad, hi + pad)
    };
    let pad = 0.05 * (hi - lo);
    let (mut lo, mut hi) = (lo - pad, hi + pad);
    let decade = 10f64.powf((hi - lo).log10().floor());
    let multiples = (hi / decade).floor() - (lo / decade).ceil() + 1.0;
    if multiples < 3.0 {
        // Out to the round values either side, then one more step on the side nearer to the
        // data's edge, until three multiples lie inside.
        lo = lo.min((lo / decade).floor() * decade);
        hi = hi.max((hi / decade).ceil() * decade);
        while ((hi - lo) / decade).round() < 2.0 {
            if hi - (hi / decade).ceil() * decade >= 0.0 && (lo / decade).fract() == 0.0 {
                hi += decade;
            } else {
                lo -= decade;
            }
        }
        let pad = 0.03 * (hi - lo);
        lo -= pad;
        hi += pad;
    }
    Some([lo, hi])
}

/// `range` (a y range) raised so that a legend of `rows` lines in the view's top corner sits above
/// the data, not on it: the data keep the lower 1 − f of the height, f = 0.06 + 0.08 · rows (a
/// line ~18 px of a ~230 px plot), at most one half.
pub fn legend_room(range: [f64; 2], rows: usize) -> [f64; 2] {
    let f = (0.06 + 0.08 * rows as f64).min(0.5);
    let [lo, hi] = range;
    [lo, hi + (hi - lo) * f / (1.0 - f)]
}

/// A view of a layout: its class, title, origin, query and the properties it opens with.
#[derive(Debug)]
pub struct View {
    id: Uuid,
    class: &'static str,
    name: String,
    origin: String,
    contents: Vec<String>,
    properties: Vec<(&'static str, Vec<SerializedComponentBatch>)>,
    /// The lines of its legend, where it shows one ([`legend_room`]).
    legend_rows: Option<usize>,
}

impl View {
    fn new(class: &'static str, name: impl Into<String>) -> View {
        View {
            id: new_id(),
            class,
            name: name.into(),
            origin: "/".into(),
            contents: vec!["$origin/**".into()],
            properties: Vec::new(),
            legend_rows: None,
        }
    }

    /// A time-series view on the time panel's timeline, opening on the whole timeline (its x range
    /// [`TimeRange::EVERYTHING`]) with its legend in the top right corner.
    pub fn time_series(name: impl Into<String>) -> View {
        View::new("TimeSeries", name)
            .with_property(
                "TimeAxis",
                &TimeAxis::new().with_view_range(
                    rerun::external::re_sdk_types::blueprint::components::TimeRange(TimeRange::EVERYTHING),
                ),
            )
            .legend(Corner2D::RightTop)
    }

    /// A 2D view.
    pub fn spatial2d(name: impl Into<String>) -> View {
        View::new("2D", name)
    }

    /// A 3D view.
    pub fn spatial3d(name: impl Into<String>) -> View {
        View::new("3D", name)
    }

    /// A text document view.
    pub fn text_document(name: impl Into<String>) -> View {
        View::new("TextDocument", name)
    }

    /// A text log view.
    pub fn text_log(name: impl Into<String>) -> View {
        View::new("TextLog", name)
    }

    /// A bar chart view.
    pub fn bar_chart(name: impl Into<String>) -> View {
        View::new("BarChart", name)
    }

    /// The view's title.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The view's origin.
    pub fn origin_path(&self) -> &str {
        &self.origin
    }

    /// The entity path this view's blueprint is logged under (`view/ID`).
    pub fn blueprint_path(&self) -> String {
        format!("view/{}", self.id)
    }

    /// The names of the properties the view opens with (`TimeAxis`, `PlotLegend`, …).
    pub fn property_names(&self) -> Vec<&'static str> {
        self.properties.iter().map(|(n, _)| *n).collect()
    }

    /// Sets the origin entity path.
    pub fn origin(mut self, origin: impl Into<String>) -> View {
        self.origin = origin.into();
        self
    }

    /// Sets the query expressions (default `$origin/**`).
    pub fn contents(mut self, queries: impl IntoIterator<Item = impl Into<String>>) -> View {
        self.contents = queries.into_iter().map(Into::into).collect();
        self
    }

    /// Sets (or replaces) a property archetype of the view, logged at `view/ID/NAME`.
    fn with_property(mut self, name: &'static str, archetype: &dyn AsComponents) -> View {
        self.properties.retain(|(n, _)| *n != name);
        self.properties.push((name, archetype.as_serialized_batches()));
        self
    }

    /// A time-series view's x range, in the timeline's units (a sequence's integers; a duration's
    /// nanoseconds).
    pub fn x_range(self, min: i64, max: i64) -> View {
        self.with_property(
            "TimeAxis",
            &TimeAxis::new().with_view_range(
                rerun::external::re_sdk_types::blueprint::components::TimeRange(TimeRange {
                    start: TimeRangeBoundary::Absolute(TimeInt(min)),
                    end: TimeRangeBoundary::Absolute(TimeInt(max)),
                }),
            ),
        )
    }

    /// A time-series view's y range, raised by [`legend_room`] where the view shows a legend.
    pub fn y_range(self, min: f64, max: f64) -> View {
        let axis = self.y_axis([min, max]);
        self.with_property("ScalarAxis", &axis)
    }

    /// The y axis opening on `range`, raised by [`legend_room`] where the view shows a legend.
    fn y_axis(&self, range: [f64; 2]) -> ScalarAxis {
        let [lo, hi] = match self.legend_rows {
            Some(rows) => legend_room(range, rows),
            None => range,
        };
        ScalarAxis::new().with_range(rerun::external::re_sdk_types::components::Range1D(Range1D([
            lo, hi,
        ])))
    }

    /// The number of lines the view's legend shows (2 unless said): the y ranges set later make
    /// room for it ([`legend_room`]); call before [`View::y_range`].
    pub fn legend_rows(mut self, rows: usize) -> View {
        if self.legend_rows.is_some() {
            self.legend_rows = Some(rows);
        }
        self
    }

    /// A time-series view's legend in `corner`.
    pub fn legend(mut self, corner: Corner2D) -> View {
        self.legend_rows = self.legend_rows.or(Some(2));
        self.with_property(
            "PlotLegend",
            &PlotLegend::new()
                .with_corner(corner)
                .with_visible(Visible::from(true)),
        )
    }

    /// A time-series view without a legend (one line, named by the title).
    pub fn no_legend(mut self) -> View {
        self.legend_rows = None;
        self.with_property(
            "PlotLegend",
            &PlotLegend::new().with_visible(Visible::from(false)),
        )
    }

    /// A 3D view's camera: an orbit about `target` from `eye`, Z up (coordinates of the view's
    /// origin).
    pub fn eye(self, eye: [f32; 3], target: [f32; 3]) -> View {
        self.with_property(
            "EyeControls3D",
            &EyeControls3D::new()
                .with_kind(Eye3DKind::Orbital)
                .with_position(eye)
                .with_look_target(target)
                .with_eye_up([0.0f32, 0.0, 1.0]),
        )
    }

    /// A 2D view's visible bounds (`x` and `y` ranges in the view's coordinates).
    pub fn bounds(self, x: [f64; 2], y: [f64; 2]) -> View {
        self.with_property(
            "VisualBounds2D",
            &VisualBounds2D::new(
                rerun::external::re_sdk_types::blueprint::components::VisualBounds2D(Range2D {
                    x_range: Range1D(x),
                    y_range: Range1D(y),
                }),
            ),
        )
    }

    fn log(&self, bp: &RecordingStream) -> RecordingStreamResult<()> {
        let path = self.blueprint_path();
        bp.log(
            format!("{path}/ViewContents"),
            &ViewContents::new(self.contents.iter().map(|q| QueryExpression(q.clone().into()))),
        )?;
        bp.log(
            path.clone(),
            &ViewBlueprint::new(ViewClass(self.class.into()))
                .with_display_name(Name(self.name.clone().into()))
                .with_space_origin(self.origin.clone()),
        )?;
        for (name, batches) in &self.properties {
            bp.log_serialized_batches(format!("{path}/{name}"), false, batches.iter().cloned())?;
        }
        Ok(())
    }
}

/// A container of a layout: views and containers side by side, one above the other, in a grid or
/// in tabs.
#[derive(Debug)]
pub struct Container {
    id: Uuid,
    kind: ContainerKind,
    name: Option<String>,
    children: Vec<Item>,
    shares: Option<Vec<f32>>,
    grid_columns: Option<u32>,
    active: Option<usize>,
}

impl Container {
    fn new(kind: ContainerKind, children: impl IntoIterator<Item = Item>) -> Container {
        Container {
            id: new_id(),
            kind,
            name: None,
            children: children.into_iter().collect(),
            shares: None,
            grid_columns: None,
            active: None,
        }
    }

    /// Children left to right.
    pub fn horizontal(children: impl IntoIterator<Item = Item>) -> Container {
        Container::new(ContainerKind::Horizontal, children)
    }

    /// Children top to bottom.
    pub fn vertical(children: impl IntoIterator<Item = Item>) -> Container {
        Container::new(ContainerKind::Vertical, children)
    }

    /// Children as tabs (the first shown).
    pub fn tabs(children: impl IntoIterator<Item = Item>) -> Container {
        Container::new(ContainerKind::Tabs, children)
    }

    /// Children in a grid of `columns` columns.
    pub fn grid(columns: u32, children: impl IntoIterator<Item = Item>) -> Container {
        let mut c = Container::new(ContainerKind::Grid, children);
        c.grid_columns = Some(columns);
        c
    }

    /// The container's name (a tab's title).
    pub fn named(mut self, name: impl Into<String>) -> Container {
        self.name = Some(name.into());
        self
    }

    /// The children's shares of the width (horizontal) or height (vertical).
    pub fn shares(mut self, shares: impl Into<Vec<f32>>) -> Container {
        self.shares = Some(shares.into());
        self
    }

    /// The tab shown first (tabs only).
    pub fn active(mut self, k: usize) -> Container {
        self.active = Some(k);
        self
    }

    /// The children.
    pub fn children(&self) -> &[Item] {
        &self.children
    }

    /// The name, if any.
    pub fn name(&self) -> Option<&str> {
        self.name.as_deref()
    }

    /// The entity path of the container's blueprint (`container/ID`).
    pub fn blueprint_path(&self) -> String {
        format!("container/{}", self.id)
    }

    /// The container's own blueprint (not its children's), with its children in `order` and the
    /// tab `active` shown.
    fn archetype(&self, order: &[usize], active: Option<usize>) -> ContainerBlueprint {
        let mut arch = ContainerBlueprint::new(self.kind).with_contents(
            order
                .iter()
                .map(|&k| IncludedContent(self.children[k].blueprint_path().into())),
        );
        if let Some(name) = &self.name {
            arch = arch.with_display_name(Name(name.clone().into()));
        }
        if let Some(shares) = &self.shares {
            let shares: Vec<f32> = order
                .iter()
                .map(|&k| shares.get(k).copied().unwrap_or(1.0))
                .collect();
            arch = match self.kind {
                ContainerKind::Horizontal => {
                    arch.with_col_shares(shares.iter().map(|&s| ColumnShare(Float32(s))))
                }
                _ => arch.with_row_shares(shares.iter().map(|&s| RowShare(Float32(s)))),
            };
        }
        if let Some(columns) = self.grid_columns {
            arch = arch.with_grid_columns(GridColumns(columns.into()));
        }
        if let Some(k) = active.filter(|&k| k < self.children.len()) {
            arch = arch.with_active_tab(ActiveTab(self.children[k].blueprint_path().as_str().into()));
        }
        arch
    }

    fn log(&self, bp: &RecordingStream) -> RecordingStreamResult<()> {
        for child in &self.children {
            child.log(bp)?;
        }
        let order: Vec<usize> = (0..self.children.len()).collect();
        bp.log(self.blueprint_path(), &self.archetype(&order, self.active))
    }
}

/// A view or a container.
#[derive(Debug)]
pub enum Item {
    View(View),
    Container(Container),
}

impl From<View> for Item {
    fn from(v: View) -> Item {
        Item::View(v)
    }
}

impl From<Container> for Item {
    fn from(c: Container) -> Item {
        Item::Container(c)
    }
}

impl Item {
    fn blueprint_path(&self) -> String {
        match self {
            Item::View(v) => v.blueprint_path(),
            Item::Container(c) => c.blueprint_path(),
        }
    }

    fn log(&self, bp: &RecordingStream) -> RecordingStreamResult<()> {
        match self {
            Item::View(v) => v.log(bp),
            Item::Container(c) => c.log(bp),
        }
    }

    /// Every view in the item, depth first.
    pub fn views(&self) -> Vec<&View> {
        match self {
            Item::View(v) => vec![v],
            Item::Container(c) => c.children.iter().flat_map(Item::views).collect(),
        }
    }

    /// The containers named `name` in the item, depth first.
    pub fn find(&self, name: &str) -> Option<&Container> {
        match self {
            Item::View(_) => None,
            Item::Container(c) if c.name.as_deref() == Some(name) => Some(c),
            Item::Container(c) => c.children.iter().find_map(|k| k.find(name)),
        }
    }
}

/// A recording's layout: its root container and the time panel's timeline and play state.
#[derive(Debug)]
pub struct Layout {
    root: Container,
    timeline: Option<String>,
    play_state: Option<PlayState>,
    time_panel: PanelState,
}

impl Layout {
    /// A layout of `root` (a view alone goes into a tab container).
    pub fn new(root: impl Into<Item>) -> Layout {
        let root = match root.into() {
            Item::Container(c) => c,
            view => Container::tabs([view]),
        };
        Layout {
            root,
            timeline: None,
            // Paused: a sweep's cursor stays where the user puts it (a run's layout follows).
            play_state: Some(PlayState::Paused),
            time_panel: PanelState::Collapsed,
        }
    }

    /// The time panel's timeline.
    pub fn timeline(mut self, timeline: impl Into<String>) -> Layout {
        self.timeline = Some(timeline.into());
        self
    }

    /// The time panel's play state (`Following` for a live run: the cursor at the newest data).
    pub fn play_state(mut self, play: PlayState) -> Layout {
        self.play_state = Some(play);
        self
    }

    /// The time panel expanded (its streams and their events shown) rather than collapsed to its
    /// bar (play, the cursor, the choice of timeline), the default: the views get the screen.
    pub fn expand_time_panel(mut self) -> Layout {
        self.time_panel = PanelState::Expanded;
        self
    }

    /// The root container.
    pub fn root(&self) -> &Container {
        &self.root
    }

    /// Every view of the layout, depth first.
    pub fn views(&self) -> Vec<&View> {
        self.root.children.iter().flat_map(Item::views).collect()
    }

    /// The container named `name`, if any.
    pub fn find(&self, name: &str) -> Option<&Container> {
        if self.root.name.as_deref() == Some(name) {
            return Some(&self.root);
        }
        self.root.children.iter().find_map(|k| k.find(name))
    }

    /// Logs the layout to a blueprint store of its own and activates it on `rec` (as the viewer's
    /// default for the application too); the returned handle changes it later.
    pub fn send(self, app_id: &'static str, rec: &RecordingStream) -> RecordingStreamResult<SentLayout> {
        let (bp, storage) = rerun::RecordingStreamBuilder::new(app_id)
            .recording_id(RecordingId::random())
            .blueprint()
            .memory()?;
        bp.set_time_sequence("blueprint", 0);
        self.root.log(&bp)?;
        bp.log(
            "viewport",
            &ViewportBlueprint::new()
                .with_root_container(RootContainer(self.root.id))
                .with_auto_layout(false)
                .with_auto_views(false),
        )?;
        let mut time = TimePanelBlueprint::new().with_state(self.time_panel);
        if let Some(t) = &self.timeline {
            time = time.with_timeline(TimelineName(t.clone().into()));
        }
        if let Some(p) = self.play_state {
            time = time.with_play_state(p);
        }
        bp.log("time_panel", &time)?;
        bp.log(
            "blueprint_panel",
            &PanelBlueprint::new().with_state(PanelState::Collapsed),
        )?;
        bp.log(
            "selection_panel",
            &PanelBlueprint::new().with_state(PanelState::Collapsed),
        )?;
        let sent = SentLayout {
            layout: self,
            bp,
            storage,
            blueprint_id: None,
        };
        Ok(sent.forward(rec))
    }
}

/// A layout sent to a recording: changes to it reach the viewer as blueprint updates.
pub struct SentLayout {
    layout: Layout,
    bp: RecordingStream,
    storage: rerun::sink::MemorySinkStorage,
    blueprint_id: Option<rerun::external::re_log_types::StoreId>,
}

impl SentLayout {
    /// Forwards what was logged to the blueprint store since the last time, and activates it.
    fn forward(mut self, rec: &RecordingStream) -> SentLayout {
        let msgs: Vec<LogMsg> = self.storage.take();
        if self.blueprint_id.is_none() {
            self.blueprint_id = msgs.first().map(|m| m.store_id().clone());
        }
        if let Some(id) = &self.blueprint_id {
            rec.send_blueprint(
                msgs,
                BlueprintActivationCommand {
                    blueprint_id: id.clone(),
                    make_active: true,
                    make_default: true,
                },
            );
        }
        self
    }

    /// Shows the tabs of the container named `name` in `order` (indices of its children), the
    /// first one active; a name no container has changes nothing.
    pub fn reorder(
        self,
        rec: &RecordingStream,
        name: &str,
        order: &[usize],
    ) -> RecordingStreamResult<SentLayout> {
        let Some(c) = self.layout.find(name) else {
            return Ok(self);
        };
        let mut seen = vec![false; c.children.len()];
        let mut full = Vec::with_capacity(seen.len());
        for &k in order.iter().chain(&(0..seen.len()).collect::<Vec<_>>()) {
            if k < seen.len() && !seen[k] {
                seen[k] = true;
                full.push(k);
            }
        }
        self.bp.set_time_sequence("blueprint", 1);
        self.bp
            .log(c.blueprint_path(), &c.archetype(&full, full.first().copied()))?;
        Ok(self.forward(rec))
    }

    /// Sets the y range of every time-series view whose origin `range_of` knows: the data's
    /// extent, widened where needed so that the axis has three labels at least ([`round_range`]),
    /// raised where the view shows a legend so that it sits above the data ([`legend_room`]).
    /// The range is a starting view: the user still zooms.
    pub fn set_y_ranges(
        self,
        rec: &RecordingStream,
        range_of: impl Fn(&str) -> Option<[f64; 2]>,
    ) -> RecordingStreamResult<SentLayout> {
        self.bp.set_time_sequence("blueprint", 1);
        for v in self.layout.views() {
            if v.class != "TimeSeries" {
                continue;
            }
            let Some(range) = range_of(&v.origin).and_then(|[a, b]| round_range(a, b)) else {
                continue;
            };
            self.bp
                .log(format!("{}/ScalarAxis", v.blueprint_path()), &v.y_axis(range))?;
        }
        Ok(self.forward(rec))
    }

    /// The layout.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The room made for a legend: the data keep the lower part of the range, the legend's band
    /// above them grows with its lines, at most half the plot.
    #[test]
    fn a_legend_gets_a_band_above_the_data() {
        let data = [-2.0, 8.0];
        for rows in [1, 2, 4, 7, 20] {
            let [lo, hi] = legend_room(data, rows);
            assert_eq!(lo, data[0]);
            let band = (hi - data[1]) / (hi - lo);
            let expected = (0.06 + 0.08 * rows as f64).min(0.5);
            assert!((band - expected).abs() < 1e-12, "{rows} rows: band {band}");
        }
        // Set through a view: the y range raised, a view without a legend left as given.
        let with = View::time_series("a").legend_rows(4).y_range(0.0, 1.0);
        let without = View::time_series("b").no_legend().y_range(0.0, 1.0);
        assert!(with.legend_rows == Some(4) && without.legend_rows.is_none());
    }
    use rerun::external::re_log_types::StoreKind;

    /// The blueprint entities a layout sends (their paths), from a memory sink, and whether it
    /// was activated.
    fn sent(
        layout: Layout,
    ) -> (
        Vec<String>,
        bool,
        SentLayout,
        RecordingStream,
        rerun::sink::MemorySinkStorage,
    ) {
        let (rec, storage) = rerun::RecordingStreamBuilder::new("kecsim-test")
            .memory()
            .unwrap();
        let sent = layout.send("kecsim-test", &rec).unwrap();
        let msgs = storage.take();
        let (paths, activated) = paths_of(&msgs);
        (paths, activated, sent, rec, storage)
    }

    fn paths_of(msgs: &[LogMsg]) -> (Vec<String>, bool) {
        let mut paths = Vec::new();
        let mut activated = false;
        for m in msgs {
            match m {
                LogMsg::ArrowMsg(store, arrow) if store.kind() == StoreKind::Blueprint => {
                    let chunk = rerun::log::Chunk::from_arrow_msg(arrow).unwrap();
                    paths.push(chunk.entity_path().to_string());
                }
                LogMsg::BlueprintActivationCommand(c) => activated |= c.make_active && c.make_default,
                _ => {}
            }
        }
        (paths, activated)
    }

    /// Every time-series view opens on its whole timeline (the x range a property of the view,
    /// logged where the viewer reads it: `view/ID/TimeAxis`); the cameras and legends likewise;
    /// the layout is activated as the application's default.
    #[test]
    fn views_open_with_their_properties() {
        let layout = Layout::new(Container::vertical([
            View::time_series("a").origin("/a").into(),
            Container::horizontal([
                View::time_series("b").origin("/b").no_legend().into(),
                View::spatial3d("c").eye([1.0, 2.0, 3.0], [0.0, 0.0, 0.5]).into(),
            ])
            .shares([2.0, 1.0])
            .into(),
        ]))
        .timeline("time");
        let views: Vec<(String, Vec<&str>)> = layout
            .views()
            .iter()
            .map(|v| (v.blueprint_path(), v.property_names()))
            .collect();
        assert_eq!(views.len(), 3);
        assert_eq!(views[0].1, vec!["TimeAxis", "PlotLegend"]);
        assert_eq!(views[1].1, vec!["TimeAxis", "PlotLegend"]);
        assert_eq!(views[2].1, vec!["EyeControls3D"]);
        let (paths, activated, ..) = sent(layout);
        assert!(activated);
        // (Entity paths read back with a leading `/`.)
        let paths: Vec<String> = paths
            .iter()
            .map(|p| p.trim_start_matches('/').to_string())
            .collect();
        for (view, props) in &views {
            assert!(paths.contains(view), "{view}: {paths:?}");
            assert!(paths.contains(&format!("{view}/ViewContents")), "{view}");
            for p in props {
                assert!(paths.contains(&format!("{view}/{p}")), "{view}/{p}: {paths:?}");
            }
        }
        for p in ["viewport", "time_panel", "blueprint_panel", "selection_panel"] {
            assert!(paths.iter().any(|x| x == p), "{p}: {paths:?}");
        }
    }

    /// y ranges that hold the data and three multiples of their decade step (three axis labels
    /// at least), not more than 3.5 × the data's span.
    #[test]
    fn y_ranges_hold_the_data_and_three_labels() {
        for (lo, hi) in [
            (-7.5, 7.5),
            (-8.3, 1.5),
            (29.3, 75.9),
            (0.0, 0.0),
            (18.996, 19.003),
            (-0.42, 3.95),
            (-4.1, 4.2),
            (0.0, 0.0071),
            (0.12, 0.19),
            (95.0, 105.0),
        ] {
            let [a, b] = round_range(lo, hi).unwrap();
            assert!(a < lo && b > hi, "{lo}..{hi}: {a}..{b}");
            let d = 10f64.powf((b - a).log10().floor());
            let inside = ((a / d).ceil() as i64..=(b / d).floor() as i64).count();
            assert!(inside >= 3, "{lo}..{hi}: {a}..{b}, step {d}");
            if hi > lo {
                assert!(b - a <= 3.5 * (hi - lo), "{lo}..{hi}: {a}..{b}");
            }
        }
        assert_eq!(round_range(f64::NAN, 1.0), None);
    }

    /// A named tab container reordered after the layout was sent: its blueprint logged again
    /// (the given tabs first, the rest after, each once) and activated; an unknown name sends
    /// nothing.
    #[test]
    fn tabs_are_reordered_later() {
        let tabs = Container::tabs(
            ["w1", "w2", "w3"].map(|n| Container::vertical([View::time_series(n).into()]).named(n).into()),
        )
        .named("wheelsets");
        let path = tabs.blueprint_path();
        let (_, _, layout, rec, storage) = sent(Layout::new(Container::vertical([tabs.into()])));
        let layout = layout.reorder(&rec, "wheelsets", &[2, 2, 7]).unwrap();
        let (paths, activated) = paths_of(&storage.take());
        assert!(activated);
        assert!(paths.iter().any(|p| p.ends_with(&path)), "{path}: {paths:?}");
        let c = layout.layout().find("wheelsets").unwrap();
        let arch = c.archetype(&[2, 0, 1], Some(2));
        assert!(format!("{arch:?}").contains(&c.children()[2].blueprint_path()));
        let layout = layout.reorder(&rec, "nothing of that name", &[1]).unwrap();
        assert!(paths_of(&storage.take()).0.is_empty());
        drop(layout);
    }
}
