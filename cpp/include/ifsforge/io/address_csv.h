#pragma once
/// @file The address table of a vector IFS as CSV.
#include <string>

#include "ifsforge/vector/addresses.h"

namespace ifsforge {

/// @brief CSV with a header: index,address,length,probability (one row per leaf), atomically.
void write_address_csv(const std::string& path, const AddressTable& addresses);

}  // namespace ifsforge
