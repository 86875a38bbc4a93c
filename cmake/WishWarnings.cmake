# Warnings on for our own targets; sanitizer flags for the whole build when WISH_SANITIZE is on.
function(wish_target_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic)
  if(WISH_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

if(WISH_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()
