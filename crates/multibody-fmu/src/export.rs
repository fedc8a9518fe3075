//! Writing an FMU: the runtime library, the model files and their
//! description, zipped. Nothing is compiled: exporting is describing and
//! zipping.

use crate::description::{model_description, Header, Kinds, Version};
use crate::model::{token, Loaded, Settings, DESCRIPTION_FILE, MODEL_FOLDER, SETTINGS_FILE};
use std::io::{Cursor, Write};
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, ZipWriter};

/// The folder of the binary for this platform, as each FMI version names it.
pub fn platform_folder(version: Version) -> String {
    let (arch, os) = (std::env::consts::ARCH, std::env::consts::OS);
    match version {
        Version::Fmi3 => format!("{arch}-{}", if os == "macos" { "darwin" } else { os }),
        Version::Fmi2 => {
            let os = match os {
                "macos" => "darwin",
                "windows" => "win",
                other => other,
            };
            format!("{os}{}", if cfg!(target_pointer_width = "64") { "64" } else { "32" })
        }
    }
}

/// The shared library's suffix on this platform.
pub const LIBRARY_SUFFIX: &str = std::env::consts::DLL_SUFFIX;

/// A model ready to export: loaded from the files as the FMU will load them.
pub struct Export {
    pub loaded: Loaded,
    /// The files as stored in `resources/model/`: name and text.
    pub files: Vec<(String, String)>,
    pub settings_json: String,
    pub token: String,
    /// The binary's name and the FMU's model identifier.
    pub identifier: String,
    pub kinds: Kinds,
    pub version: Version,
}

impl Export {
    /// Loads `files` (names as the user gave them) as the FMU will: the
    /// analysis or component chosen, the extra `outputs`, which kinds and
    /// which version (`None`: the `FMUAnalysis`'s, else both kinds of FMI
    /// 2.0).
    pub fn prepare(
        files: &[(String, String)],
        analysis: Option<String>,
        model: Option<String>,
        outputs: Vec<String>,
        kinds: Option<Kinds>,
        version: Option<Version>,
    ) -> Result<Export, String> {
        let files = stored_names(files);
        let settings = Settings { files: files.iter().map(|(n, _)| n.clone()).collect(), analysis, model, outputs };
        let loaded = Loaded::load(&files, &settings)?;
        let kinds = kinds.unwrap_or(match &loaded.lowered.study {
            multibody_dyad::Study::Fmu { model_exchange, co_simulation, .. } => {
                Kinds { model_exchange: *model_exchange, co_simulation: *co_simulation }
            }
            _ => Kinds { model_exchange: true, co_simulation: true },
        });
        let version = version.unwrap_or(match &loaded.lowered.study {
            multibody_dyad::Study::Fmu { version: 3, .. } => Version::Fmi3,
            _ => Version::Fmi2,
        });
        let settings_json = settings.to_json();
        let identifier = identifier(&loaded.lowered.name);
        let mut export = Export { loaded, files, settings_json, token: String::new(), identifier, kinds, version };
        // The token covers the description, written without it.
        export.token = token(&export.settings_json, &export.files, &export.model_description());
        Ok(export)
    }

    pub fn model_description(&self) -> String {
        let header = Header {
            model_name: &self.loaded.lowered.name,
            identifier: &self.identifier,
            token: &self.token,
            kinds: self.kinds,
            options: &self.loaded.options,
            version: self.version,
        };
        model_description(&header, &self.loaded.interface)
    }

    /// The FMU's bytes: a zip with forward slashes, deflated.
    pub fn archive(&self, runtime: &[u8]) -> Result<Vec<u8>, String> {
        let mut zip = ZipWriter::new(Cursor::new(Vec::new()));
        let deflated = SimpleFileOptions::default().compression_method(CompressionMethod::Deflated);
        let mut add = |name: &str, bytes: &[u8]| -> Result<(), String> {
            // The binary is most of the bytes: the fastest level keeps an
            // export well under a second.
            let level = if bytes.len() > 1 << 20 { Some(1) } else { None };
            zip.start_file(name, deflated.compression_level(level)).map_err(|e| format!("cannot zip {name}: {e}"))?;
            zip.write_all(bytes).map_err(|e| format!("cannot zip {name}: {e}"))
        };
        add(DESCRIPTION_FILE, self.model_description().as_bytes())?;
        add(&format!("binaries/{}/{}{LIBRARY_SUFFIX}", platform_folder(self.version), self.identifier), runtime)?;
        add(&format!("resources/{SETTINGS_FILE}"), self.settings_json.as_bytes())?;
        for (name, text) in &self.files {
            add(&format!("resources/{MODEL_FOLDER}/{name}"), text.as_bytes())?;
        }
        let cursor = zip.finish().map_err(|e| format!("cannot finish the zip: {e}"))?;
        Ok(cursor.into_inner())
    }
}

/// Each file under its own name (`model.dyad`), made unique.
fn stored_names(files: &[(String, String)]) -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = Vec::new();
    for (path, text) in files {
        let base =
            std::path::Path::new(path).file_name().map_or("model.dyad".into(), |n| n.to_string_lossy().into_owned());
        let mut name = base.clone();
        let mut k = 2;
        while out.iter().any(|(n, _)| *n == name) {
            name = format!("{k}_{base}");
            k += 1;
        }
        out.push((name, text.clone()));
    }
    out
}

/// A C identifier from the model's name (the binary's file name).
pub fn identifier(name: &str) -> String {
    let mut id: String = name.chars().map(|c| if c.is_ascii_alphanumeric() { c } else { '_' }).collect();
    if id.is_empty() || id.starts_with(|c: char| c.is_ascii_digit()) {
        id.insert(0, 'm');
    }
    id
}
