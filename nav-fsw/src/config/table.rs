//! The macro that turns the parameter table (`parameters.rs`) into [`super::Param`]: one
//! variant per declaration, and from the declarations its path, unit, default, range, reason,
//! replay-setup word, accessors and check. A `macro_rules!` table rather than a derive: nav-fsw
//! is `no_std` and takes no proc-macro.

/// One arm per declaration:
///
/// ```text
/// Name: type {
///     path: "block.key_unit", unit: "s", default: Some(value) | None (given by the mission),
///     word: Some(index) | None (not in the replay setup),
///     range: Range::new(low, high)..., why: "the reason for the range",
///     get: |config| ..., set: |config, value| ...,
///     [when: Flag (the parameter applies only while the flag parameter `Flag` is on)]
/// }
/// ```
macro_rules! flight_parameters {
    ($(
        $name:ident: $type:ty {
            path: $path:literal,
            unit: $unit:literal,
            default: $default:expr,
            word: $word:expr,
            range: $range:expr,
            why: $why:expr,
            get: $get:expr,
            set: $set:expr
            $(, when: $flag:ident)? $(,)?
        }
    )*) => {
        /// Every flight parameter, one variant per declaration of the parameter table
        /// (`nav-fsw/src/config/parameters.rs`; docs/reference/flight-parameters.md).
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        #[cfg_attr(feature = "defmt", derive(defmt::Format))]
        pub enum Param {
            $(
                #[doc = concat!("`", $path, "` (", $unit, ")")]
                $name,
            )*
        }

        impl Param {
            /// Every parameter in table order.
            pub const ALL: &'static [Param] = &[$(Param::$name),*];

            /// The parameter's path in [`FswConfig`], e.g. `timing.max_latency_s`.
            pub const fn path(self) -> &'static str {
                match self { $(Param::$name => $path,)* }
            }

            /// The parameter's unit (`""` for a dimensionless number, a count or a choice).
            pub const fn unit(self) -> &'static str {
                match self { $(Param::$name => $unit,)* }
            }

            /// The values the parameter accepts.
            pub const fn range(self) -> Range {
                match self { $(Param::$name => $range,)* }
            }

            /// Why the range is what it is (physics, numerics or the frame budget).
            pub const fn why(self) -> &'static str {
                match self { $(Param::$name => $why,)* }
            }

            /// The parameter's word in the replay setup ([`crate::replay::ReplaySetup`]),
            /// `None` where the replay takes the default.
            pub const fn word(self) -> Option<usize> {
                match self { $(Param::$name => $word,)* }
            }

            /// The parameter's value in `config` as a number ([`ParamValue::to_number`]).
            pub fn value(self, config: &FswConfig) -> f64 {
                match self {
                    $(Param::$name => {
                        let get: fn(&FswConfig) -> $type = $get;
                        ParamValue::to_number(get(config))
                    })*
                }
            }

            /// The default as a number; `None` for a value the mission gives.
            pub fn default_value(self) -> Option<f64> {
                match self {
                    $(Param::$name => {
                        let default: Option<$type> = $default;
                        default.map(ParamValue::to_number)
                    })*
                }
            }

            /// The flag parameter the parameter applies under (a second head's parameters
            /// under `star.second_head`), `None` if it always applies.
            pub const fn condition(self) -> Option<Param> {
                match self {
                    $(Param::$name => flight_parameters!(@condition $($flag)?),)*
                }
            }

            /// Whether the parameter applies to `config` ([`Self::condition`] on).
            pub fn applies(self, config: &FswConfig) -> bool {
                self.condition().is_none_or(|flag| flag.value(config) != 0.0)
            }

            /// Whether `word` is a value of the parameter's type (a replay-setup word).
            pub fn decodes(self, word: u64) -> bool {
                match self {
                    $(Param::$name => <$type as ParamValue>::from_word(word).is_some(),)*
                }
            }

            /// The value of a replay-setup word as a number ([`ParamValue::to_number`]);
            /// `None` for a word that is no value of the parameter's type.
            pub fn word_number(self, word: u64) -> Option<f64> {
                match self {
                    $(Param::$name => {
                        <$type as ParamValue>::from_word(word).map(ParamValue::to_number)
                    })*
                }
            }

            /// Sets the default (nothing for a value the mission gives).
            pub(crate) fn set_default(self, config: &mut FswConfig) {
                match self {
                    $(Param::$name => {
                        let set: fn(&mut FswConfig, $type) = $set;
                        let default: Option<$type> = $default;
                        if let Some(value) = default {
                            set(config, value);
                        }
                    })*
                }
            }

            /// The value in `config` as its replay-setup word.
            pub fn to_word(self, config: &FswConfig) -> u64 {
                match self {
                    $(Param::$name => {
                        let get: fn(&FswConfig) -> $type = $get;
                        ParamValue::to_word(get(config))
                    })*
                }
            }

            /// Sets the value from a number ([`ParamValue::from_number`]), as nav-sim sets a
            /// scenario's values.
            ///
            /// # Errors
            /// [`FswError::InvalidConfiguration`] naming the parameter for a number that is no
            /// value of its type; `config` is unchanged then.
            pub fn set_number(self, config: &mut FswConfig, number: f64) -> Result<(), FswError> {
                let invalid = FswError::InvalidConfiguration(ConfigField::Parameter(self));
                match self {
                    $(Param::$name => {
                        let set: fn(&mut FswConfig, $type) = $set;
                        set(config, <$type as ParamValue>::from_number(number).ok_or(invalid)?);
                    })*
                }
                Ok(())
            }

            /// Sets the value from its replay-setup word.
            ///
            /// # Errors
            /// [`FswError::InvalidConfiguration`] naming the parameter for a word that is no
            /// value of its type (a count beyond it, an index that names no choice);
            /// `config` is unchanged then.
            pub fn set_word(self, config: &mut FswConfig, word: u64) -> Result<(), FswError> {
                let invalid = FswError::InvalidConfiguration(ConfigField::Parameter(self));
                match self {
                    $(Param::$name => {
                        let set: fn(&mut FswConfig, $type) = $set;
                        set(config, <$type as ParamValue>::from_word(word).ok_or(invalid)?);
                    })*
                }
                Ok(())
            }
        }
    };
    (@condition) => { None };
    (@condition $flag:ident) => { Some(Param::$flag) };
}

pub(super) use flight_parameters;
