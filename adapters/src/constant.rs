//! The ROS constant message: a message whose one number field holds one of its constants
//! (`tier4_rtc_msgs/Command`, `autoware_adapi_v1_msgs/CooperationDecision`, …), declared once by
//! [`constant_message!`].
//!
//! The field holds any number, as on the wire: whether it is a constant is decided where the
//! message is converted into the core's types, so that the error names the field. Where the
//! constants stand for one of the core's enums, the macro writes the table once, both ways.

/// Declares a constant message: the struct (the derives every message has; its serde
/// attributes are given), its constants, `new`, `constant_name`, and, given `=> Enum::Variant`
/// for every constant that stands for one, `meaning` (the variant of a value, if it is a
/// constant that has one), `of` and `From<Enum>` (the value of a variant).
macro_rules! constant_message {
    (
        $(#[$meta:meta])*
        pub struct $name:ident {
            $(#[$field_meta:meta])*
            pub $field:ident: $ty:ty
        }
        meaning $enum:ty;
        $(
            $(#[$constant_meta:meta])*
            const $constant:ident = $value:literal $(=> $variant:path)?;
        )*
    ) => {
        $crate::constant::constant_message! {
            $(#[$meta])*
            pub struct $name {
                $(#[$field_meta])*
                pub $field: $ty
            }
            $(
                $(#[$constant_meta])*
                const $constant = $value;
            )*
        }

        impl $name {
            /// What the value stands for, if it is a constant that stands for something.
            #[must_use]
            pub const fn meaning(&self) -> Option<$enum> {
                match self.$field {
                    $($(Self::$constant => Some($variant),)?)*
                    _ => None,
                }
            }

            /// The message whose constant stands for `meaning`.
            #[must_use]
            pub const fn of(meaning: $enum) -> Self {
                Self::new(match meaning {
                    $($($variant => Self::$constant,)?)*
                })
            }
        }

        impl From<$enum> for $name {
            fn from(meaning: $enum) -> Self {
                Self::of(meaning)
            }
        }
    };
    (
        $(#[$meta:meta])*
        pub struct $name:ident {
            $(#[$field_meta:meta])*
            pub $field:ident: $ty:ty
        }
        $(
            $(#[$constant_meta:meta])*
            const $constant:ident = $value:literal;
        )*
    ) => {
        #[derive(
            Clone,
            Copy,
            PartialEq,
            Eq,
            PartialOrd,
            Ord,
            Hash,
            Debug,
            Default,
            serde::Serialize,
            serde::Deserialize,
        )]
        $(#[$meta])*
        pub struct $name {
            $(#[$field_meta])*
            pub $field: $ty,
        }

        impl $name {
            $(
                $(#[$constant_meta])*
                pub const $constant: $ty = $value;
            )*

            /// The message with this value.
            #[must_use]
            pub const fn new($field: $ty) -> Self {
                Self { $field }
            }

            /// The name of the constant the value is, if it is one: the type as this crate names
            /// it and the constant as ROS does (`CooperationDecision.UNKNOWN`; `Lifecycle.RUNNING`
            /// for `tier4_rtc_msgs/State`'s `RUNNING`).
            #[must_use]
            pub const fn constant_name(&self) -> Option<&'static str> {
                match self.$field {
                    $(Self::$constant => Some(concat!(stringify!($name), ".", stringify!($constant))),)*
                    _ => None,
                }
            }
        }
    };
}

pub(crate) use constant_message;

#[cfg(test)]
mod tests {
    use cooperation::{Decision, OperatorDecision, Phase};

    use crate::rtc::{Command, Lifecycle, Module, ModuleType};
    use crate::wire::CooperationDecision;

    /// Every value that has a meaning gives it back, and no two values share one.
    macro_rules! both_ways {
        ($message:ty, $field:ident, $meanings:expr) => {{
            let mut seen = 0;
            for value in 0..=u8::MAX {
                let message = <$message>::new(value);
                if let Some(meaning) = message.meaning() {
                    assert_eq!(<$message>::of(meaning).$field, value);
                    assert!(message.constant_name().is_some(), "{value}");
                    seen += 1;
                }
            }
            for meaning in $meanings {
                assert_eq!(<$message>::of(meaning).meaning(), Some(meaning));
            }
            seen
        }};
    }

    #[test]
    fn each_meaning_is_one_constant_both_ways() {
        assert_eq!(
            both_ways!(Command, r#type, [Decision::Deactivate, Decision::Activate]),
            2
        );
        let phases = [
            Phase::Waiting,
            Phase::Running,
            Phase::Aborting,
            Phase::Succeeded,
            Phase::Failed,
        ];
        assert_eq!(both_ways!(Lifecycle, r#type, phases), 5);
        assert_eq!(both_ways!(Module, r#type, ModuleType::ALL), 20);
        let operator = [
            OperatorDecision::Deactivate,
            OperatorDecision::Activate,
            OperatorDecision::Autonomous,
            OperatorDecision::Undecided,
        ];
        assert_eq!(both_ways!(CooperationDecision, decision, operator), 4);
    }

    #[test]
    fn constants_are_named_as_ros_writes_them() {
        assert_eq!(
            CooperationDecision::new(0).constant_name(),
            Some("CooperationDecision.UNKNOWN")
        );
        assert_eq!(CooperationDecision::new(0).meaning(), None);
        assert_eq!(Module::new(19).constant_name(), Some("Module.ROUNDABOUT"));
        assert_eq!(Module::new(20).constant_name(), None);
        assert_eq!(Lifecycle::new(5).meaning(), None);
    }
}
