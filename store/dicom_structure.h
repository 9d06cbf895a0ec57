// The element structure of a DICOM part-10 file, checked before GDCM reads it: GDCM, as Debian builds it,
// stops the process on an assertion where a file is cut short (an interrupted copy), and reads a pixel data
// element cut short as if it were whole. Without GDCM; a pure function of the file; any thread.
#pragma once

#include <string>

namespace ropecast {

// Why the file at `path` is not whole, in words ("" when it is): the signature, the file meta group and the
// data set walked element by element (in the transfer syntax the meta group names), each declared length
// within its file or item, each sequence and item of undefined length closed by its delimiter, each explicit
// value representation one the standard defines. The data set of a deflated transfer syntax is not walked.
std::string dicomStructureProblem(const std::string& path);

}  // namespace ropecast
