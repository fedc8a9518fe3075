//! Writing an FMU: the runtime library, the model files and their
//! description, zipped. Nothing is compiled: exporting is describing and
//! zipping.

use crate::description::{model_description, Header, Kinds};
use crate::model::{token, Loaded, Settings, MODEL_FOLDER, SETTINGS_FILE};
use std::io::{Cursor, Write};
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, ZipWriter};

/// The folder of the binary for this platform, as FMI 2.0 names it.
pub const PLATFORM_FOLDER: &str = if cfg!(all(target_os = "linux", target_pointer_width = "64")) {
    "linux64"
} else if cfg!(all(target_os = "macos", target_pointer_width = "64")) {
    "darwin64"
} else if cfg!(all(target_os = "windows", target_pointer_width = "64")) {
    "win64"
} else {
    "unsupported"
};

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
}

impl Export {
    /// Loads `files` (names as the user gave them) as the FMU will: the
    /// analysis or component chosen, the extra `outputs`, and which kinds
    /// (`None`: the `FMUAnalysis`'s, else both).
    pub fn prepare(
        files: &[(String, String)],
        analysis: Option<String>,
        model: Option<String>,
        outputs: Vec<String>,
        kinds: Option<Kinds>,
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
        let settings_json = settings.to_json();
        let token = token(&settings_json, &files);
        let identifier = identifier(&loaded.lowered.name);
        Ok(Export { loaded, files, settings_json, token, identifier, kinds })
    }

    /// The FMI version the model's `FMUAnalysis` asks for (2 without one).
    pub fn asked_version(&self) -> u8 {
        match &self.loaded.lowered.study {
            multibody_dyad::Study::Fmu { version, .. } => *version,
            _ => 2,
        }
    }

    pub fn model_description(&self) -> String {
        let header = Header {
            model_name: &self.loaded.lowered.name,
            identifier: &self.identifier,
            token: &self.token,
            description: None,
            kinds: self.kinds,
            options: &self.loaded.options,
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
        add("modelDescription.xml", self.model_description().as_bytes())?;
        add(&format!("binaries/{PLATFORM_FOLDER}/{}{LIBRARY_SUFFIX}", self.identifier), runtime)?;
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
