//! The one declaration of the packet layout: each kind's APID, name, purpose and the output
//! words its data field carries ([`PACKETS`]). The encoder, the ground decoder
//! (nav-sim `logs::telemetry_packets`) and docs/reference/telemetry-packets.md read it.

use crate::replay::{OUTPUT_FIELD_NAMES, OUTPUT_WORDS};

/// The kinds of telemetry packet, one APID each (a closed set: a ground decoder refuses any
/// other APID).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum PacketKind {
    /// The navigation solution, the frame's fusion, NIS and sensor verdicts.
    Navigation,
    /// The calibration estimates and their 1σ.
    Calibration,
    /// The optional state blocks' estimates and their 1σ.
    OptionalStates,
    /// The health counters: input faults, gates, resets, drops, overruns, outages; and the
    /// command counters, so the packet that reports the computer's housekeeping also
    /// verifies a command (its accepted or refused count steps).
    Health,
    /// The configuration warnings: the monitors that say the configured models do not fit
    /// what the sensors show.
    ConfigurationWarnings,
}

/// Number of packet kinds.
pub const PACKET_KIND_COUNT: usize = 5;

impl PacketKind {
    /// Every kind, in [`PACKETS`] order.
    pub const ALL: [Self; PACKET_KIND_COUNT] = [
        Self::Navigation,
        Self::Calibration,
        Self::OptionalStates,
        Self::Health,
        Self::ConfigurationWarnings,
    ];

    /// The kind's place in [`PACKETS`] and [`Self::ALL`].
    pub const fn index(self) -> usize {
        match self {
            Self::Navigation => 0,
            Self::Calibration => 1,
            Self::OptionalStates => 2,
            Self::Health => 3,
            Self::ConfigurationWarnings => 4,
        }
    }

    /// The kind's declaration.
    pub const fn declaration(self) -> &'static PacketDeclaration {
        match self {
            Self::Navigation => &PACKETS[0],
            Self::Calibration => &PACKETS[1],
            Self::OptionalStates => &PACKETS[2],
            Self::Health => &PACKETS[3],
            Self::ConfigurationWarnings => &PACKETS[4],
        }
    }

    /// The kind of an APID, `None` for one no kind has.
    pub fn of_apid(apid: u16) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|kind| kind.declaration().apid == apid)
    }
}

/// How a word is read: an IEEE-754 binary64 bit pattern or an unsigned integer (counters,
/// flags, bit sets, enumerations).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum WordType {
    /// `f64` bits.
    Float,
    /// `u64`.
    Unsigned,
}

/// A run of consecutive output words in a packet's data field.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct WordSpan {
    /// Index of the first word in the output record (`OUTPUT_FIELD_NAMES`), resolved from its
    /// name at compile time (a name that is not an output word fails the build).
    pub first: usize,
    /// Number of words.
    pub count: usize,
    /// How the words are read.
    pub word_type: WordType,
}

impl WordSpan {
    /// `count` words from the output word called `first_name`.
    const fn named(first_name: &str, count: usize, word_type: WordType) -> Self {
        Self {
            first: output_word_index(first_name),
            count,
            word_type,
        }
    }

    /// The output word indices of the span (empty for an unresolved span).
    pub fn indices(&self) -> core::ops::Range<usize> {
        if self.first >= OUTPUT_WORDS {
            return 0..0;
        }
        self.first..self.first.saturating_add(self.count).min(OUTPUT_WORDS)
    }
}

/// Index of the output word `name`, [`OUTPUT_WORDS`] if there is none (const: the table
/// resolves its names at compile time).
const fn output_word_index(name: &str) -> usize {
    let mut index = 0;
    let mut rest = OUTPUT_FIELD_NAMES.as_slice();
    while let Some((field, tail)) = rest.split_first() {
        if str_equal(field, name) {
            return index;
        }
        index += 1;
        rest = tail;
    }
    OUTPUT_WORDS
}

const fn str_equal(a: &str, b: &str) -> bool {
    let (mut a, mut b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    while let (Some((x, a_tail)), Some((y, b_tail))) = (a.split_first(), b.split_first()) {
        if *x != *y {
            return false;
        }
        a = a_tail;
        b = b_tail;
    }
    true
}

/// One packet kind: its APID, name, what it is for and its data field's words.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PacketDeclaration {
    /// The kind.
    pub kind: PacketKind,
    /// Its Application Process Identifier (11 bits).
    pub apid: u16,
    /// Its name (lower case, for rates and reports).
    pub name: &'static str,
    /// What it carries, for people.
    pub purpose: &'static str,
    /// The output words of its data field, in order, after the secondary header.
    pub words: &'static [WordSpan],
}

impl PacketDeclaration {
    /// Words of the data field (after the secondary header).
    pub const fn data_words(&self) -> usize {
        let mut total = 0;
        let mut rest = self.words;
        while let Some((span, tail)) = rest.split_first() {
            total += span.count;
            rest = tail;
        }
        total
    }

    /// Bytes of the whole packet: primary header, secondary header, data words, CRC.
    pub const fn packet_bytes(&self) -> usize {
        super::PRIMARY_HEADER_BYTES
            + super::SECONDARY_HEADER_BYTES
            + 8 * self.data_words()
            + super::CRC_BYTES
    }
}

use WordType::{Float, Unsigned};

/// The packet kinds (module docs). The output words `frame` and `time_s` are every packet's
/// secondary header ([`super::SECONDARY_HEADER_WORDS`]); every other output word is in the
/// data field of exactly one kind (a test checks).
pub const PACKETS: [PacketDeclaration; PACKET_KIND_COUNT] = [
    PacketDeclaration {
        kind: PacketKind::Navigation,
        apid: 0x101,
        name: "navigation",
        purpose: "the navigation solution, the measurement fused in the frame, the last NIS, \
                  the sensor verdicts and the active star head",
        words: &[
            WordSpan::named("attitude_w", 10, Float),
            WordSpan::named("fusion", 1, Unsigned),
            WordSpan::named("last_star_nis", 2, Float),
            WordSpan::named("star_faulty", 4, Unsigned),
            WordSpan::named("last_gnss_velocity_nis", 1, Float),
            WordSpan::named("inconsistent_aids", 1, Unsigned),
            WordSpan::named("star_active_head", 1, Unsigned),
        ],
    },
    PacketDeclaration {
        kind: PacketKind::Calibration,
        apid: 0x102,
        name: "calibration",
        purpose: "the calibration estimates (gyro and accelerometer bias, star installation, \
                  gyro and accelerometer scale factor), then their filter 1σ",
        words: &[WordSpan::named("gyro_bias_x", 30, Float)],
    },
    PacketDeclaration {
        kind: PacketKind::OptionalStates,
        apid: 0x103,
        name: "optional-states",
        purpose: "the optional state blocks flown (`optional_blocks` bits), then the \
                  correlated GNSS error's and the systematic IMU errors' estimates and 1σ \
                  (NaN for a block not flown)",
        words: &[
            WordSpan::named("optional_blocks", 1, Unsigned),
            WordSpan::named("gnss_error_x_m", 30, Float),
        ],
    },
    PacketDeclaration {
        kind: PacketKind::Health,
        apid: 0x104,
        name: "health",
        purpose: "the health counters: input faults, stale and future measurements, gate \
                  rejections, covariance repairs, resets, sensors declared faulty, drops, \
                  frame overruns, sensor outages; then the command counters: commands \
                  accepted and refused, measurements of a sensor disabled by command, \
                  calibration records loaded and refused",
        words: &[
            WordSpan::named("imu_non_finite", 23, Unsigned),
            WordSpan::named("gnss_velocity_gate_rejections", 2, Unsigned),
            WordSpan::named("imu_records_dropped", 1, Unsigned),
            WordSpan::named("gravity_field_errors", 1, Unsigned),
            WordSpan::named("star_pair_rejections", 1, Unsigned),
            WordSpan::named("star_head_handovers", 1, Unsigned),
            WordSpan::named("frame_overruns", 8, Unsigned),
        ],
    },
    PacketDeclaration {
        kind: PacketKind::ConfigurationWarnings,
        apid: 0x105,
        name: "configuration-warnings",
        purpose: "the monitors that say the configuration does not fit the flight: correlated \
                  or inconsistent innovations, the inertial solution suspected, a gravity \
                  allowance too short, the star noise matched (and its values), the heads' \
                  alignment moving, an unknown head, an uncorrected aberration",
        words: &[
            WordSpan::named("gnss_innovations_correlated", 1, Unsigned),
            WordSpan::named("star_inconsistent", 3, Unsigned),
            WordSpan::named("inertial_suspect", 2, Unsigned),
            WordSpan::named("star_noise_matched", 1, Unsigned),
            WordSpan::named("star_noise_x_rad", 3, Float),
            WordSpan::named("star_heads_inconsistent", 1, Unsigned),
            WordSpan::named("star_unknown_head", 1, Unsigned),
            WordSpan::named("star_aberration_suspected", 1, Unsigned),
        ],
    },
];

/// How output word `index` is read: `frame` unsigned, `time_s` a float, any other word as
/// its packet declares it (unsigned for an index beyond the record).
pub fn word_type(index: usize) -> WordType {
    if index == 1 {
        return Float;
    }
    PACKETS
        .iter()
        .flat_map(|packet| packet.words.iter())
        .find(|span| span.indices().contains(&index))
        .map_or(Unsigned, |span| span.word_type)
}

/// Most data words of any kind.
pub const MAX_DATA_WORDS: usize = {
    let mut most = 0;
    let mut rest = PACKETS.as_slice();
    while let Some((packet, tail)) = rest.split_first() {
        if packet.data_words() > most {
            most = packet.data_words();
        }
        rest = tail;
    }
    most
};

/// Bytes of one frame's packets when every kind is due: the buffer
/// [`super::PacketEncoder::encode_frame`] needs at most.
pub const MAX_FRAME_PACKET_BYTES: usize = {
    let mut total = 0;
    let mut rest = PACKETS.as_slice();
    while let Some((packet, tail)) = rest.split_first() {
        total += packet.packet_bytes();
        rest = tail;
    }
    total
};

/// Every span resolves to output words (a name that is not one fails the build).
const _: () = {
    let mut packets = PACKETS.as_slice();
    while let Some((packet, packets_tail)) = packets.split_first() {
        let mut spans = packet.words;
        while let Some((span, spans_tail)) = spans.split_first() {
            assert!(span.first + span.count <= OUTPUT_WORDS);
            spans = spans_tail;
        }
        packets = packets_tail;
    }
};
