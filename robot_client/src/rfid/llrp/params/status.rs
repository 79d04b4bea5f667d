//! `LLRPStatus` (LLRP 1.0.1 §16.2.8.1): every response's verdict, and the reader's own words
//! when it refuses.

use std::fmt;

use super::super::wire::{DecodeError, Decoded, FieldReader, Param, tlv, utf8v};

pub const LLRP_STATUS: u16 = 287;
const FIELD_ERROR: u16 = 288;
const PARAMETER_ERROR: u16 = 289;

/// A response's status: success, or a code with the reader's description of what it refused.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LlrpStatus {
    pub code: u16,
    pub description: String,
    /// Which field of the message was wrong (its index) and how.
    pub field_error: Option<FieldError>,
    /// Which parameter was wrong and how.
    pub parameter_error: Option<ParameterError>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FieldError {
    pub field_num: u16,
    pub error_code: u16,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParameterError {
    pub parameter_type: u16,
    pub error_code: u16,
    pub field_error: Option<FieldError>,
}

impl LlrpStatus {
    pub const SUCCESS: u16 = 0;

    pub fn success() -> Self {
        Self {
            code: Self::SUCCESS,
            description: String::new(),
            field_error: None,
            parameter_error: None,
        }
    }

    pub fn is_success(&self) -> bool {
        self.code == Self::SUCCESS
    }

    pub fn encode(&self, out: &mut Vec<u8>) {
        tlv(out, LLRP_STATUS, |out| {
            out.extend_from_slice(&self.code.to_be_bytes());
            utf8v(out, &self.description);
            if let Some(field) = self.field_error {
                field.encode(out);
            }
            if let Some(param) = &self.parameter_error {
                tlv(out, PARAMETER_ERROR, |out| {
                    out.extend_from_slice(&param.parameter_type.to_be_bytes());
                    out.extend_from_slice(&param.error_code.to_be_bytes());
                    if let Some(field) = param.field_error {
                        field.encode(out);
                    }
                });
            }
        });
    }

    pub fn decode(param: Param<'_>) -> Decoded<Self> {
        let mut r = param.fields();
        let code = r.u16("LLRPStatus's status code")?;
        let description = r.utf8v("LLRPStatus's error description")?;
        let mut status = Self { code, description, field_error: None, parameter_error: None };
        while let Some(p) = r.param()? {
            match p.kind {
                FIELD_ERROR => status.field_error = Some(FieldError::decode(p)?),
                PARAMETER_ERROR => {
                    let mut r = p.fields();
                    let mut error = ParameterError {
                        parameter_type: r.u16("ParameterError's parameter type")?,
                        error_code: r.u16("ParameterError's error code")?,
                        field_error: None,
                    };
                    // A nested ParameterError may follow; its outer one says enough.
                    while let Some(p) = r.param()? {
                        if p.kind == FIELD_ERROR {
                            error.field_error = Some(FieldError::decode(p)?);
                        }
                    }
                    status.parameter_error = Some(error);
                }
                _ => {}
            }
        }
        Ok(status)
    }

    /// The status of a response body: its first parameter must be an `LLRPStatus`.
    pub fn first_in(r: &mut FieldReader<'_>, message: &str) -> Decoded<Self> {
        match r.param()? {
            Some(p) if p.kind == LLRP_STATUS && !p.tv => Self::decode(p),
            Some(p) => Err(DecodeError(format!(
                "{message} begins with parameter type {} where LLRPStatus belongs",
                p.kind
            ))),
            None => Err(DecodeError(format!("{message} has no LLRPStatus"))),
        }
    }
}

impl FieldError {
    fn encode(&self, out: &mut Vec<u8>) {
        tlv(out, FIELD_ERROR, |out| {
            out.extend_from_slice(&self.field_num.to_be_bytes());
            out.extend_from_slice(&self.error_code.to_be_bytes());
        });
    }

    fn decode(param: Param<'_>) -> Decoded<Self> {
        let mut r = param.fields();
        Ok(Self {
            field_num: r.u16("FieldError's field number")?,
            error_code: r.u16("FieldError's code")?,
        })
    }
}

/// The spec's name of a status code (Table 16.2.8.1), for messages a person reads.
pub fn status_code_name(code: u16) -> &'static str {
    match code {
        0 => "M_Success",
        100 => "M_ParameterError",
        101 => "M_FieldError",
        102 => "M_UnexpectedParameter",
        103 => "M_MissingParameter",
        104 => "M_DuplicateParameter",
        105 => "M_OverflowParameter",
        106 => "M_OverflowField",
        107 => "M_UnknownParameter",
        108 => "M_UnknownField",
        109 => "M_UnsupportedMessage",
        110 => "M_UnsupportedVersion",
        111 => "M_UnsupportedParameter",
        112 => "M_UnexpectedMessage",
        200 => "P_ParameterError",
        201 => "P_FieldError",
        202 => "P_UnexpectedParameter",
        203 => "P_MissingParameter",
        204 => "P_DuplicateParameter",
        205 => "P_OverflowParameter",
        206 => "P_OverflowField",
        207 => "P_UnknownParameter",
        208 => "P_UnknownField",
        209 => "P_UnsupportedParameter",
        300 => "A_Invalid",
        301 => "A_OutOfRange",
        401 => "R_DeviceError",
        _ => "an unknown status",
    }
}

impl fmt::Display for LlrpStatus {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ({})", status_code_name(self.code), self.code)?;
        if !self.description.is_empty() {
            write!(f, ": \"{}\"", self.description)?;
        }
        if let Some(p) = &self.parameter_error {
            write!(
                f,
                " (in parameter type {}, {})",
                p.parameter_type,
                status_code_name(p.error_code)
            )?;
        }
        if let Some(e) = self.field_error {
            write!(f, " (field {}, {})", e.field_num, status_code_name(e.error_code))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_refusal_round_trips_and_reads_as_the_reader_said_it() {
        let status = LlrpStatus {
            code: 100,
            description: "no ROSpec 7".into(),
            field_error: None,
            parameter_error: Some(ParameterError {
                parameter_type: 177,
                error_code: 201,
                field_error: Some(FieldError { field_num: 0, error_code: 301 }),
            }),
        };
        let mut bytes = Vec::new();
        status.encode(&mut bytes);
        let mut r = FieldReader::new(&bytes);
        assert_eq!(LlrpStatus::first_in(&mut r, "a test").unwrap(), status);
        assert_eq!(
            status.to_string(),
            "M_ParameterError (100): \"no ROSpec 7\" (in parameter type 177, P_FieldError)"
        );
    }
}
